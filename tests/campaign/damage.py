"""Damage a Parquet file the way a bad disk sector does: one value column's page, nothing else;
write an edited table as the tool writes one (:func:`as_written`)."""

from __future__ import annotations

from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from graspcampaign.campaign.verify import CONTENT_KEY, content_digest


def corrupt_value_column(path: Path, column: str) -> None:
    """Flip bytes in ``column``'s first column chunk; footer and key pages intact.

    Asserts the damage is of the kind the store must catch: the footer still reads, the
    ``trial_id`` pages still pass checksum verification, and a full verified read fails.
    """
    meta = pq.ParquetFile(path).metadata
    index = meta.schema.to_arrow_schema().get_field_index(column)
    chunk = meta.row_group(0).column(index)
    # the last bytes of the dictionary page (its values), or of the only data page: past any
    # page header, so the file still parses and only the checksum can tell
    if chunk.has_dictionary_page:
        end = chunk.data_page_offset
    else:
        end = chunk.data_page_offset + chunk.total_compressed_size
    data = bytearray(path.read_bytes())
    for offset in range(end - 4, end):
        data[offset] ^= 0x5A
    path.write_bytes(bytes(data))
    pq.read_schema(path)  # footer intact
    pq.read_table(path, columns=["trial_id"], page_checksum_verification=True)  # key pages fine
    try:
        pq.read_table(path, page_checksum_verification=True)
    except OSError:
        return
    raise AssertionError(f"flipping bytes of {column} in {path} did not damage a checked page")


def as_written(table: pa.Table, target: Path) -> None:
    """Write ``table`` as ``target`` as the tool writes a file: with the digest of its values."""
    meta = {**(table.schema.metadata or {}), CONTENT_KEY: content_digest(table).encode()}
    pq.write_table(table.replace_schema_metadata(meta), target, write_page_checksum=True)
