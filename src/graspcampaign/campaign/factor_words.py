"""The words for a factor a study's trial kind never reads: compose refuses one in a study file
(:func:`graspcampaign.campaign.studycheck.check_kind`), and an override naming a known factor the
study does not vary (``mu=[0.3]`` on smoke) says so rather than advise adding it."""

from __future__ import annotations

from graspcampaign.campaign.schema import example


def it_reads(reads: list[str]) -> str:
    """``it reads shape, nodes`` (``it reads no factor``): what a trial kind reads, in a sentence."""
    return f"it reads {', '.join(reads)}" if reads else "it reads no factor"


def not_a_factor(name: str, rejected: str, factors: list[str], reads: tuple[str, list[str]] | None) -> str:
    """``reads``: the study's trial kind and the factors it reads (None: unknown, or not declared)."""
    said = f"{name} is not a factor of this study ({rejected}; its factors: {', '.join(factors) or 'none'})"
    if reads and name not in reads[1]:  # adding it would be refused too: its kind never reads it
        return f"{said}, and the {reads[0]} kind does not read it ({it_reads(reads[1])})."
    return f"{said}; add it with +factors.{name}={example(name)}."
