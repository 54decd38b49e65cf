"""Bad input, round 9: what round 8 found and left (a near-miss material, a PLY claiming more
vertices than it holds, a gzipped mesh, a manifest of newer code, an escaped quote in a mapping
override, an output name whose suffix says another format) and the odd inputs of round 9's table
(the final report of branch bad9).
Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

import bz2
import gzip
import json
import lzma
import zipfile
from pathlib import Path

import pytest
import trimesh
from cli_checks import SMOKE, invoke, refused

from graspcampaign.campaign.provenance import code_version


@pytest.mark.parametrize(("material", "meant"), [
    ("silicone_rf", "did you mean 'silicone_ref'? "),  # it had no suggestion and no final period
    ("steel", ""),
])
def test_a_near_miss_material_is_suggested_in_a_sentence(tmp_path, sphere, material, meant):
    refused(tmp_path, ["plan", sphere, "--mass-kg", "0.1", "--material", material, "--png",
                       tmp_path / "p.png"],
            f"--material '{material}' is not a Table 4 material family; {meant}use one of gel, "
            "silicone_soft, bio_foam, silicone_ref.")


def _binary_ply(path: Path, vertices: int | None = None, faces: int | None = None) -> None:
    """The sphere as a binary PLY whose header declares ``vertices`` / ``faces`` elements."""
    mesh = trimesh.creation.icosphere(subdivisions=2, radius=40.0)
    data = mesh.export(file_type="ply", encoding="binary")
    if vertices is not None:
        data = data.replace(b"element vertex %d\n" % len(mesh.vertices), b"element vertex %d\n" % vertices)
    if faces is not None:
        data = data.replace(b"element face %d\n" % len(mesh.faces), b"element face %d\n" % faces)
    path.write_bytes(data)


@pytest.mark.parametrize(("vertices", "faces", "declared", "least"), [
    # it said "cannot be read as PLY (PLY is unexpected length!)."
    (2_000_000_000, None, "2,000,000,000 vertex", 2_000_000_000 * 12),
    (None, 10**9, "162 vertex and 1,000,000,000 face", 162 * 12 + 10**9),  # a list: its count alone
])
def test_a_binary_ply_declaring_more_than_it_holds_is_named(tmp_path, vertices, faces, declared,
                                                            least):
    path = tmp_path / "big.ply"
    _binary_ply(path, vertices, faces)
    after = path.stat().st_size - path.read_bytes().index(b"end_header\n") - len(b"end_header\n")
    refused(tmp_path, ["plan", path, "--mass-kg", "0.1"],
            f"mesh 'big.ply' is truncated or its header is wrong: its header declares {declared} "
            f"elements, at least {least:,} bytes of binary data, but the file holds only {after:,} "
            "bytes after its header.")


@pytest.mark.parametrize(("name", "pack", "what", "todo"), [
    # it said "... 3499 bytes are neither a binary STL (84 bytes plus 50 per triangle) nor ..."
    ("sphere.stl", gzip.compress, "a gzip-compressed file, not an STL", "decompress it first (gunzip)"),
    ("sphere.ply", bz2.compress, "a bzip2-compressed file, not a PLY", "decompress it first (bunzip2)"),
    ("sphere.obj", lzma.compress, "an xz-compressed file, not an OBJ", "decompress it first (unxz)"),
    ("sphere.stl", None, "a zip archive, not an STL", "extract the mesh from it first (unzip)"),
])
def test_a_compressed_mesh_file_is_named_as_one(tmp_path, sphere, name, pack, what, todo):
    path = tmp_path / "packed" / name
    path.parent.mkdir()
    if pack is None:
        with zipfile.ZipFile(path, "w") as archive:
            archive.write(sphere, "sphere.stl")
    else:
        path.write_bytes(pack(sphere.read_bytes()))
    refused(tmp_path, ["plan", path, "--mass-kg", "0.1"],
            f"mesh '{name}' is {what} file itself: {todo} and give the mesh it holds.")


def _stored_by(run: Path, version: str, layout: int | None = None) -> None:
    """Make the run's manifest say a code of ``version`` stored it (in file layout ``layout``)."""
    path = run / "manifest.json"
    manifest = json.loads(path.read_text())
    manifest["code_version"] = version
    if layout is not None:
        manifest["format"] = layout
    path.write_text(json.dumps(manifest))


@pytest.mark.parametrize("command", ["status", "report", "run"])
def test_a_run_stored_in_a_later_file_layout_is_refused_naming_both_versions(results, command):
    """A manifest of newer code was read without a word, whatever its files' layout."""
    run = results / "smoke" / "default"
    _stored_by(run, "9.0.0+0123456789ab", layout=2)
    refused(results, [command, "smoke", *(SMOKE if command == "run" else []), "--root", results],
            f"run smoke/default at {run} was stored by graspcampaign 9.0.0+0123456789ab in file "
            f"layout 2, and this code ({code_version()}) reads layout 1 at most; read it with "
            "graspcampaign 9.0.0 or later.")


def test_a_run_stored_by_a_later_release_in_this_layout_is_read_with_a_warning(results):
    run = results / "smoke" / "default"
    _stored_by(run, "9.0.0+0123456789ab")
    status = invoke("status", "smoke", "--root", results)
    assert status.exit_code == 0, status.output
    assert status.stderr == ("warning: run smoke/default was stored by graspcampaign "
                             f"9.0.0+0123456789ab, a later release than this code ({code_version()}); "
                             "it is read as this code reads it.\n")
    _stored_by(run, "0.0.1+0123456789ab")  # an earlier release: no word
    assert invoke("status", "smoke", "--root", results).stderr == ""


def test_a_new_manifest_records_its_file_layout(results):
    manifest = json.loads((results / "smoke" / "default" / "manifest.json").read_text())
    assert manifest["format"] == 1


@pytest.mark.parametrize("value", [
    # the escaped quote ended the string for the key scan, which then read the rest as one string
    r"{shape:['a\'b'],shape:[sphere]}",
    r'{shape:["a\"b"],shape:[sphere]}',
    r"{'sh\'ape':[sphere],shape:[sphere],shape:[pear]}",
])
def test_a_key_repeated_beside_an_escaped_quote_in_a_mapping_is_refused(tmp_path, value):
    refused(tmp_path, ["show", "smoke", f"factors={value}", "--root", tmp_path / "results"],
            f"override {f'factors={value}'!r} names factors.shape twice; give it once (Hydra would "
            "keep the last silently).")


@pytest.mark.parametrize("name", ["times.csv", "times.JSON", "times.xlsx"])
def test_reproduce_times_named_as_another_format_is_refused(results, tmp_path, name):
    """``reproduce --times times.csv`` appended '== smoke: 3 s' lines to a file named as CSV."""
    times = tmp_path / name
    refused(results, ["reproduce", "--times", times, "--root", results],
            f"--times {times}: reproduce appends lines of text ('== <step>: <s> s') to it, not "
            f"{times.suffix}; give --times {times.with_suffix('.txt')}.")


@pytest.mark.parametrize("name", ["day1.png", "day1.md", "day1.yaml"])
def test_a_schedule_out_named_as_a_picture_or_a_page_is_refused(results, tmp_path, name):
    """``schedule --out day1.png`` wrote day1.png.csv and day1.png.parquet (round 8 refused only
    .xlsx, .xls, .json, .txt and .tsv)."""
    out = tmp_path / name
    refused(results, ["schedule", "test3_disturbance", "--out", out, "--root", results],
            f"--out {out}: schedule writes the sheet as CSV and Parquet (<stem>.csv and "
            f"<stem>.parquet), not as {out.suffix}; give --out {tmp_path / 'day1'} or "
            f"{tmp_path / 'day1.csv'}.")


def test_a_schedule_out_ending_in_csv_in_capitals_names_the_stem(results, tmp_path):
    """``--out day1.CSV`` wrote day1.CSV.csv and day1.CSV.parquet; day1.csv names the stem day1."""
    done = invoke("schedule", "test3_disturbance", "--out", tmp_path / "day1.CSV", "--root", results)
    assert done.exit_code == 0, done.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["day1.csv", "day1.parquet", "results"]


# -- round 9's table: the odd inputs tried beyond the brief --------------------------------------
@pytest.mark.parametrize(("args", "what", "wanted"), [
    (["plan", "{path}", "--mass-kg", "0.1"], "{path}", "a mesh file (STL, OBJ or PLY)"),
    (["show", "{path}"], "study file {path}", "a YAML file"),
    (["ingest", "test2_grasp", "{path}"], "{path}", "a file of measured records (CSV, XLSX or Parquet)"),
])
@pytest.mark.parametrize("link", ["to a missing file", "in a loop"])
def test_a_symlink_leading_nowhere_is_named_as_one(results, tmp_path, args, what, wanted, link):
    """Each said "no such file" (or "does not exist") of a path that is there: a link."""
    path = tmp_path / "given.yaml"
    if link == "in a loop":
        (tmp_path / "other.yaml").symlink_to(path)
        path.symlink_to(tmp_path / "other.yaml")
        why = "is a symbolic link in a loop (it leads back to itself)"
    else:
        path.symlink_to(tmp_path / "moved" / "given.yaml")
        why = f"is a symbolic link to {tmp_path / 'moved' / 'given.yaml'}, which does not exist"
    rooted = [] if args[0] == "plan" else ["--root", results]
    refused(results, [*(a.format(path=path) for a in args), *rooted],
            f"{what.format(path=path)} {why}; give {wanted}.")


def test_a_binary_stl_cut_short_is_named_as_one(tmp_path, sphere):
    """It said "8042 bytes are neither a binary STL (84 bytes plus 50 per triangle) nor an ASCII
    STL"; a file of other bytes keeps that sentence."""
    cut, other = tmp_path / "cut.stl", tmp_path / "other.stl"
    cut.write_bytes(sphere.read_bytes()[:8042])
    refused(tmp_path, ["plan", cut, "--mass-kg", "0.1"],
            "mesh 'cut.stl' is truncated or its header is wrong: its header declares 320 triangles, "
            "16,084 bytes as a binary STL (84 plus 50 per triangle), but the file holds only 8,042 "
            "bytes.")
    other.write_bytes(bytes(80) + (4_000_000_000).to_bytes(4, "little") + bytes(5000))
    refused(tmp_path, ["plan", other, "--mass-kg", "0.1"],
            "mesh 'other.stl' is not an STL file: 5084 bytes are neither a binary STL (84 bytes "
            "plus 50 per triangle) nor an ASCII STL (text starting with 'solid').")


@pytest.mark.parametrize(("study", "override", "reads"), [
    ("sensitivity", "+factors.mu=[0.1]", "reads no factor"),
    ("test2_grasp", "+factors.shape=[sphere]", "reads no factor"),
    ("dynamic_check", "+factors.nodes=[390]",
     "reads only the factors model_preset, shape, mass_kg, mu and planner")])
def test_a_factor_a_study_of_an_explicit_design_never_reads_is_refused(results, study, override, reads):
    """``show sensitivity +factors.mu=[0.1]`` was accepted and ran the same 2,160 trials under
    another config hash: a kind that builds its own trial list reads only its own factors."""
    name = override.split("=")[0].removeprefix("+")
    refused(results, ["show", study, override, "--root", results],
            f"study {study!r} (trial kind {study!r}) builds its own trial list from its params and "
            f"{reads}: {name} would change nothing but the config hash; set its params instead "
            f"(graspcampaign show {study} lists them).")



# -- one check of a file given to read (campaign/paths.py input_file_problem) ---------------------
@pytest.mark.parametrize(("args", "what", "wanted"), [
    (["plan", "{path}", "--mass-kg", "0.1"], "{path}", "a mesh file (STL, OBJ or PLY)"),
    (["show", "{path}"], "study file {path}", "a YAML file"),
    (["ingest", "test2_grasp", "{path}"], "{path}", "a file of measured records (CSV, XLSX or Parquet)"),
])
@pytest.mark.parametrize("given", ["a directory", "nothing", "a name under a file"])
def test_a_file_to_read_that_is_a_directory_or_missing_is_named_alike(results, tmp_path, args, what,
                                                                      wanted, given):
    """The three commands said it three ways: "is a directory" (plan), "is a directory, not a file
    of measured records" (ingest), "is a directory, not a file" (show); ": no such mesh file"
    (plan), ": no such file" (ingest), "does not exist" (show)."""
    path = tmp_path / "given.yaml"
    if given == "a directory":
        path.mkdir()
    elif given == "a name under a file":
        path.write_text("")
        path = path / "inner.yaml"
    why = "is a directory, not a file" if given == "a directory" else "does not exist"
    rooted = [] if args[0] == "plan" else ["--root", results]
    refused(results, [*(a.format(path=path) for a in args), *rooted],
            f"{what.format(path=path)} {why}; give {wanted}.")
