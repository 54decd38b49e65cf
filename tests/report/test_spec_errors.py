"""A contributor's mistake in a report spec gets one sentence naming the spec or item and what is
wrong: at import for an entry that is no item, a Finding without its function or two tables of one
name; in the item's note for a compute returning no DataFrame or rates grouped by a column the records
lack; under the table for a shown column its frame lacks. Before, these crashed with a traceback,
printed '<built-in method title of str ...>', showed '—' in every row unexplained, or said the
table was empty."""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re

import pandas as pd
import pytest

import graspcampaign.report.studies as studies
from graspcampaign.report.build import KIND_SPECS, SPECS
from graspcampaign.report.document import Document, cols
from graspcampaign.report.render import Run, render
from graspcampaign.report.spec import Figure, Finding, Rates, ReportSpec, Table, Value

RECORDS = pd.DataFrame({"trial_id": ["a", "b", "c", "d"], "status": "ok", "shape": "sphere",
                        "planner": ["heuristic", "heuristic", "random", "random"],
                        "mass_kg": [0.2, 0.4, 0.2, 0.4], "success": [True, False, False, False]})


def by_mass(run: Run) -> pd.DataFrame:
    return run.ok.groupby("mass_kg")["success"].mean().mul(100).rename("success_pct").reset_index()


def notes(*items) -> tuple[list[str], list[str]]:
    """The notes the page shows and the run's failures after rendering ``items``."""
    run = Run(RECORDS, {"study": "mini", "config": {"factors": {}}})
    doc = render(ReportSpec("mini", items), run, Document("mini", "simulation", []))
    return [b.markdown for b in doc.blocks if getattr(b, "kind", "") == "note"], run.failures


@pytest.mark.parametrize("items, message", [
    ([Finding(lambda run: "x"), Rates], "report spec 'mini', item 2: the function Rates is not a report "
                                        "item (Finding, Section, Text, Table, Figure, Value); call it."),
    (["oops"], "report spec 'mini', item 1: a str (oops) is not a report item"),
    (cols("mass_kg"), "report spec 'mini', item 1: a Col (Col(key='mass_kg'"),
    ([Finding("the heuristic wins")], "report spec 'mini', item 1: Finding takes a function of the run "
                                      "returning its paragraph, not a str."),
])
def test_an_entry_that_is_no_report_item_is_named_at_import(items, message):
    with pytest.raises(TypeError, match="^" + re.escape(message)):
        ReportSpec("mini", items)


def test_two_tables_of_one_name_are_refused_at_import():
    with pytest.raises(ValueError, match=r"^report spec 'mini': two tables are named 'by_mass' \(one would "
                                         r"overwrite the other's file\); name them apart\.$"):
        ReportSpec("mini", [Table("by_mass", "a", by_mass), Value("v", "s", lambda run: 1.0),
                            Table("by_mass", "b", by_mass)])


def test_a_shown_column_the_frame_lacks_is_named_under_its_table():
    # still shown as "—" (a run recorded before a column existed keeps its table), but said
    shown, failures = notes(Table("by_mass", "c", by_mass, ["mass_kg", "succes_pct", "n_grasps"]))
    # each column with its own nearest (it said "(nearest: `success_pct`)" after both, of neither)
    assert shown == failures == ["Table by_mass shows `succes_pct` (did you mean 'success_pct'?), "
                                 "`n_grasps`, not in its frame: shown as —."]


def test_a_compute_returning_a_series_says_so():
    # a TypeError (the spec's mistake, counted as a failed item), not a ValueError (the data's reason)
    shown, _ = notes(Table("rate", "c", lambda run: run.ok.groupby("planner")["success"].mean()))
    assert shown == ["Table rate not computed: TypeError: its compute returned a Series, not a DataFrame "
                     "(a grouped result needs .reset_index())."]


def test_rates_by_a_column_the_records_lack_name_it_instead_of_an_empty_table():
    shown, _ = notes(Rates("by_planner", "c", ["plannr"]))
    assert shown == ["Table by_planner not computed: the records have no `plannr` column."]


def broken(*items) -> tuple[list[str], list[str]]:
    """The notes the page shows and the items whose code failed (``Run.broken``)."""
    run = Run(RECORDS, {"study": "mini", "config": {"factors": {}}})
    doc = render(ReportSpec("mini", items), run, Document("mini", "simulation", []))
    return [b.markdown for b in doc.blocks if getattr(b, "kind", "") == "note"], run.broken


def draws(table: str):
    def draw(run: Run, fig) -> None:
        fig.subplots().plot(run.tables[table]["success_pct"])
    return draw


def test_a_table_name_the_spec_declares_nowhere_is_the_items_failure_with_the_near_name():
    # before: "its table by_mas was not computed", counted as the data's reason (exit 0), though no
    # table of that name exists
    shown, failed = broken(Table("by_mass", "c", by_mass), Figure("f", "c", draws("by_mas"), (3, 2)))
    assert shown == ["Figure f not computed: LookupError: this report declares no table by_mas; did you "
                     "mean 'by_mass'? its tables: by_mass."]
    assert failed == ["Figure f"]


def test_a_table_read_by_an_item_above_it_is_the_items_failure_saying_where_to_declare_it():
    # before: "its table by_mass was not computed", though the table is computed, right below
    shown, failed = broken(Figure("f", "c", draws("by_mass"), (3, 2)), Table("by_mass", "c", by_mass))
    assert shown == ["Figure f not computed: LookupError: table by_mass is declared below this item, so it "
                     "is not computed yet; declare it above the items that read it."]
    assert failed == ["Figure f"]


def test_a_declared_table_not_computed_stays_the_datas_reason_and_a_finding_reads_any_table():
    def fails(run: Run) -> pd.DataFrame:
        raise ValueError("no executed trial")

    shown, failed = broken(Finding(lambda run: f"{len(run.tables['by_mass'])} masses."),
                           Table("none", "c", fails), Figure("f", "c", draws("none"), (3, 2)),
                           Table("by_mass", "c", by_mass))
    assert shown == ["Table none not computed: no executed trial.",
                     "Figure f not computed: its table none was not computed."]
    assert failed == []


def test_every_spec_of_the_studies_package_is_registered():
    # a spec module left out of SPECS is silently replaced by its compare_with or kind spec
    registered = {*SPECS.values(), *KIND_SPECS.values()}
    found = {f"{m.name}:{attr}" for m in pkgutil.iter_modules(studies.__path__)
             for attr, value in inspect.getmembers(importlib.import_module(f"{studies.__name__}.{m.name}"))
             if isinstance(value, ReportSpec)}
    assert found - registered == set(), ("report/studies holds specs no entry of build.SPECS or "
                                         "KIND_SPECS reaches: add them to SPECS")


def test_every_rate_shown_with_its_wilson_interval_is_headed_by_the_one_helper():
    # readings, the surrogate's class balance and accuracy built the column by hand and printed
    # "% (95%)" where every other rate printed "% (Wilson 95%)": one interval, two names
    from graspcampaign.report.build import spec_for
    from graspcampaign.report.document import Col, pct_col

    by_hand = []
    for study in {**SPECS, **KIND_SPECS}:
        for item in spec_for(study, study).items:
            shown = getattr(item, "cols", None)
            for c in shown if isinstance(shown, list | tuple) else ():
                rate = isinstance(c, Col) and c.key.endswith("_pct") and c.key[:-4]
                if rate and (c.low, c.high) == (f"{rate}_low_pct", f"{rate}_high_pct") and \
                        c != pct_col(rate, c.label.removesuffix(" % (Wilson 95%)"), of=c.of):  # its own n
                    by_hand.append(f"{study}: {item.name}: {c.label!r}")
    assert by_hand == []


def test_a_paper_column_beside_a_value_with_a_unit_is_headed_in_that_unit():
    # Tables 6-9 and test3_coating headed the paper's n, rates and thresholds "paper" beside
    # "n", "success % (Wilson 95%)" and "median threshold [N]"
    import re

    from graspcampaign.report.build import spec_for
    from graspcampaign.report.document import Col

    bare = []
    for study in {**SPECS, **KIND_SPECS}:
        for item in spec_for(study, study).items:
            shown = [c for c in getattr(item, "cols", None) or () if isinstance(c, Col)] \
                if not callable(getattr(item, "cols", None)) else []
            for ours, paper in zip(shown, shown[1:], strict=False):
                unit = re.search(r"(^n$| %( |$)|\[[^\]]+\]$)", ours.label)  # n, "rate % (…)", "x [N]"
                if paper.key.startswith(("paper", "n_paper")) and unit and paper.label == "paper":
                    bare.append(f"{study}: {item.name}: {paper.key} beside {ours.label!r}")
    assert bare == []
