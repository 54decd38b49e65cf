"""The §7 claims of the ``test1_bench`` report (table test1_claims) and the per-event frames they and
its other items read (``FRAMES``, over the run's fitted events)."""

from __future__ import annotations

import pandas as pd

from graspcampaign.analysis import calibration as cal
from graspcampaign.analysis.records import Estimate
from graspcampaign.analysis.vocabulary import label
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Claims, Value, share


def fitted(run: Run, block: str | None = None, *need: str) -> pd.DataFrame:
    """The run's fitted events (of ``block`` if given) whose ``need`` columns all hold."""
    f = run.memo("fitted", lambda: cal.fitted(run.records))
    f = f[f["block"] == block] if block else f
    return f[f[list(need)].all(axis=1)] if need else f


FRAMES = {
    "accepted": lambda r: fitted(r, "normal", "fit_ok", "accepted"),
    "normal": lambda r: fitted(r, "normal"),
    "flagged": lambda r: fitted(r, "normal").query("~accepted"),
    "sliding": lambda r: fitted(r, "sliding", "fit_ok"),
    "relaxation": lambda r: fitted(r, "relaxation", "fit_ok"),
    "cool_dry": lambda r: FRAMES["sliding"](r).query("environment == 'cool_dry'"),
    "warm_humid": lambda r: FRAMES["sliding"](r).query("environment == 'warm_humid'"),
    "oblique": lambda r: cal.oblique_summary(fitted(r)), "cyclic": lambda r: cal.cyclic_summary(fitted(r)),
    "damage": lambda r: r.memo("damage", lambda: cal.damage_summary(
        r.part("summary/damage_depth"), r.part("summary/truths"), r.radius_mm)),
    "last_cycle": lambda r: FRAMES["cyclic"](r).sort_values("cycle_index").groupby("specimen_id").tail(1)}


def _v(frame: str, col: str, how: str = "mean"):
    """A Value: ``how`` of ``col`` over ``FRAMES[frame]`` (lowest/highest family mean; share: Wilson)."""
    def value(run: Run) -> Estimate:
        if not len(f := FRAMES[frame](run)):
            raise ValueError(f"no {frame.replace('_', ' ')} event in the records")
        if how == "share":
            return share(f, f[col])
        v = f.groupby("material")[col].mean() if how in ("lowest", "highest") else f[col]
        return Estimate(float(v.agg({"lowest": "min", "highest": "max"}.get(how, how))), n=len(f))
    return value


#: the claims' rows the opening (:func:`graspcampaign.report.studies.test1.finding`) reads, named once
#: here, where CLAIMS declares them: a row renamed is renamed where the opening looks it up
N_MEAN, RMSE_MEAN = "contact exponent n, accepted fits: mean", "force-fit RMSE, accepted fits: mean"
LOOP_MEDIAN = "loop area: median"
#: the normal quantile of a two-sided 95% Wald interval
WALD_95 = 1.96


def opening_rows(claims: pd.DataFrame) -> list[pd.Series]:
    """The rows :data:`N_MEAN`, :data:`RMSE_MEAN` and :data:`LOOP_MEDIAN` of table test1_claims, which the
    opening reads; one it lacks is the code's failure (LookupError: the opening is broken), never a
    silent gap."""
    rows, names = claims.set_index("quantity"), (N_MEAN, RMSE_MEAN, LOOP_MEDIAN)
    if missing := [q for q in names if q not in rows.index]:
        raise LookupError(f"table test1_claims has no row {missing[0]!r}, which the opening reads")
    return [rows.loc[q] for q in names]


def _t4(col: str):
    return lambda p: (min(getattr(r, col) for r in p.table4.values()),
                      max(getattr(r, col) for r in p.table4.values()))


def c_unresolved(run: Run) -> bool:
    """Whether per-event C is not identifiable: the median event's Wald 95% interval, median C ± 1.96 median
    standard errors (the claims rows :data:`C_ROWS`, computed as table test1_claims computes them: Table 4's
    caption above it cannot read it), reaches zero (a row not computed: False)."""
    c, se = Claims("test1_claims", "", C_ROWS).compute(run)["value"]
    return bool(abs(c) <= WALD_95 * se)


def _pair(what: str, sec: str, frame: str, col: str, paper, unit: str = "", digits: int = 2,
          hows=("lowest", "highest"), of: str = "family") -> list[Value]:
    return [Value(f"{what}: {h} {of}", sec, _v(frame, col, w), paper, unit, digits)
            for h, w in zip(("lowest", "highest"), hows, strict=True)]


#: the claims' rows for per-event C: the normal fits' median C and median standard error
C_ROWS = (Value("per-event C: median (paper: Table 4's family range)", "§7.2",
                _v("normal", "c_n_s_per_m", "median"), _t4("c_n_s_per_m"), "N s/m", 3),
          Value("standard error of per-event C: median", "§7.2", _v("normal", "c_se_n_s_per_m", "median"),
                None, "N s/m"))
CLAIMS = [
    Value(N_MEAN, "§7.2", _v("accepted", "n_exp"),
          lambda p: p.n_exp_mean),
    Value("contact exponent n, accepted fits: SD", "§7.2", _v("accepted", "n_exp", "std"),
          lambda p: p.n_exp_sd),
    *_pair("mean n per family", "§7.2", "accepted", "n_exp", lambda p: p.n_exp_family_range),
    Value(RMSE_MEAN, "§7.2", _v("accepted", "rmse_pct"),
          lambda p: p.rmse_pct_accepted, "%"),
    Value("force-fit RMSE, all normal fits: mean", "§7.2", _v("normal", "rmse_pct"),
          lambda p: p.rmse_pct_all, "%"),
    *_pair("RMSE of the review-flagged fits", "§7.2", "flagged", "rmse_pct",
           lambda p: p.flagged_rmse_pct_range, "%", 1, ("min", "max"), "fit"),
    # at the decimals §7.2 prints: "0.082 mJ", "median loading work 0.54 mJ, median unloading 0.42 mJ"
    *(Value(row, "§7.2", _v("normal", f"{w}_mj", "median"),
            lambda p, w=w: getattr(p, f"{w}_median_mj"), "mJ", digits)
      for w, row, digits in (("loop_area", LOOP_MEDIAN, 3), ("loading_work", "loading work: median", 2),
                             ("unloading_work", "unloading work: median", 2))),
    *C_ROWS,
    *(Value(f"μs {label('environment', e)}: campaign mean", "§7.3", _v(e, "mu_s"),
            lambda p, e=e: p.mu_s_environment[e]) for e in ("cool_dry", "warm_humid")),
    Value("μs > μk in every family", "Table 4", lambda r: bool(r.tables["table4"].query("row == 'ours'").eval(
        "mu_s > mu_k").all()), lambda p: all(r.mu_s > r.mu_k for r in p.table4.values())),
    # §7.3: "k_t in the 2 N mm^{-1} to 5 N mm^{-1} range", whole newtons per millimetre
    *_pair("kt per family", "§7.3", "sliding", "k_t_n_per_mm", lambda p: p.k_t_range_n_per_mm, "N/mm", 0),
    Value("Coulomb prediction = sign of the slip margin", "§7.3",
          _v("oblique", "classification_matches_margin", "share"),
          lambda p: p.oblique_classification_match_pct, "%", 1),
    Value("Coulomb prediction = slip on the bench", "§7.3",
          _v("oblique", "classification_matches_measured", "share"), None, "%", 1),
    *_pair("ρ per family", "§7.4", "relaxation", "rho", _t4("rho")),
    *_pair("τ per family", "§7.4", "relaxation", "tau_s", _t4("tau_s"), "s", 1),
    # §7.4, Fig. 25: K/K1 "remains above the 0.85 durability target", a one-sided bound (no upper end)
    Value("K/K1 at the last measured cycle: lowest specimen (paper: above the target)", "§7.4",
          _v("last_cycle", "k_ratio", "min"), lambda p: (p.k_ratio_target, None), digits=3,
          bound="the paper's durability target"),
    *_pair("permanent set after cycling", "§7.4", "last_cycle", "permanent_set_mm",
           lambda p: p.permanent_set_mm, "mm", of="family mean"),
]
