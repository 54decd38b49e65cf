"""What ``core.words.meant`` suggests across the tool's real vocabularies, under candidate rules.

Vocabularies: every config section's keys, each kind's ``params`` keys, the factors, studies,
trial kinds, materials, planners, shapes, model presets, report and figure formats, mesh units and
panels. Typos of a name ``w`` (the right answer is ``w``): every deletion, adjacent transposition,
doubling of one character, and a substitution by the next letter (a stand-in for a neighbouring
key), for names of 3 characters or more. Words that are not names (the right answer is the name
listed beside each, or none): a fixed, hand-labelled list of what a user of another tool types.
Prints, per rule, the counts (right / wrong / none) and the table of the labelled words and the
typos the tests pin (docs/decisions.md, "The near-miss rule").

    PYTHONPATH=src python benchmarks/near_miss_table.py
"""

import dataclasses
import difflib
import string

from graspcampaign.campaign import schema
from graspcampaign.campaign.catalog import kind_facts, registry_names
from graspcampaign.campaign.kind import KINDS
from graspcampaign.campaign.kinds.mesh_resolution import PANELS as RESOLUTION_PANELS
from graspcampaign.campaign.kinds.sensitivity import PANELS as SENSITIVITY_PANELS
from graspcampaign.campaign.studyfile import group_options, list_studies
from graspcampaign.core.bench import FAMILIES
from graspcampaign.core.mesh import SHAPES, UNITS
from graspcampaign.core.words import meant
from graspcampaign.report.document import FIGURE_FORMATS, FORMATS


def vocabularies() -> dict[str, list[str]]:
    """Every set of names a user types and the tool checks with ``meant``."""
    study = schema.StudyCfg()
    out = {"study config": [f.name for f in dataclasses.fields(study)]}
    for f in dataclasses.fields(study):
        if dataclasses.is_dataclass(section := getattr(study, f.name)):
            out[f.name] = [g.name for g in dataclasses.fields(section)]
    for kind in sorted(KINDS):
        spec = kind_facts(kind).get("params")
        if spec:
            out[f"params of {kind}"] = [name for name, _, _ in spec["fields"]]
    out |= {"factors": sorted(schema.FACTOR_SPECS), "studies": list_studies(), "kinds": sorted(KINDS),
            "materials": list(FAMILIES), "planners": list(registry_names("planner")),
            "shapes": list(SHAPES), "model presets": list(group_options("model")),
            "report formats": list(FORMATS), "figure formats": list(FIGURE_FORMATS),
            "units": list(UNITS), "backends": ["loky", "dask", "sequential"],
            "sensitivity panels": list(SENSITIVITY_PANELS),
            "mesh_resolution panels": list(RESOLUTION_PANELS)}
    return out


def typos(word: str) -> set[str]:
    """Single-edit typos of ``word``: deletions, adjacent transpositions, doublings, next-letter
    substitutions."""
    out = set()
    for i in range(len(word)):
        out.add(word[:i] + word[i + 1:])
        out.add(word[:i] + word[i] + word[i:])
        if i + 1 < len(word):
            out.add(word[:i] + word[i + 1] + word[i] + word[i + 2:])
        if word[i] in string.ascii_lowercase:
            out.add(word[:i] + string.ascii_lowercase[(string.ascii_lowercase.index(word[i]) + 1) % 26]
                    + word[i + 1:])
    out.discard(word)
    return {t for t in out if t}


def osa(a: str, b: str) -> int:
    """Optimal string alignment distance (Levenshtein with adjacent transpositions)."""
    d = [[i + j if i * j == 0 else 0 for j in range(len(b) + 1)] for i in range(len(a) + 1)]
    for i in range(1, len(a) + 1):
        for j in range(1, len(b) + 1):
            d[i][j] = min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1]))
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                d[i][j] = min(d[i][j], d[i - 2][j - 2] + 1)
    return d[-1][-1]


def _ratios(word, known):
    """(ratio, name), best first, scored as difflib.get_close_matches scores."""
    return sorted(((difflib.SequenceMatcher(None, k, word).ratio(), k) for k in known), reverse=True)


def rule_before(word, known):
    """before: difflib's one nearest (a tie to the larger name), cutoff 0.6"""
    typed = word.strip().lower()
    if typed in known:
        return [typed]
    return difflib.get_close_matches(typed, known, n=1, cutoff=0.6)


def rule_cutoff(cut):
    def rule(word, known):
        return difflib.get_close_matches(word.strip().lower(), known, n=1, cutoff=cut)
    rule.__doc__ = f"difflib's one nearest, cutoff {cut}"
    return rule


def rule_no_tie(word, known):
    """none on a tie (cutoff 0.6)"""
    ranked = _ratios(word.strip().lower(), known)
    if not ranked or ranked[0][0] < 0.6 or (len(ranked) > 1 and ranked[1][0] == ranked[0][0]):
        return []
    return [ranked[0][1]]


def rule_edits(word, known):
    """before, kept within max(1, len/3) edits (OSA)"""
    near = rule_before(word, known)
    return [n for n in near if osa(word.lower(), n) <= max(1, len(word) // 3)]


def rule_shipped(word, known):
    """after: `meant`, every name tied at the best ratio"""
    return meant(word, known).split("'")[1::2]


RULES = [rule_before, rule_cutoff(0.7), rule_no_tie, rule_edits, rule_shipped]


def _label(rule):
    return rule.__doc__.splitlines()[0]


#: what a user types that is no name here, each with the name it means (None: no name means it)
LABELLED = [
    ("runner", "cores", "n_jobs"), ("runner", "workers", "n_jobs"), ("runner", "threads", "n_jobs"),
    ("runner", "jobs", "n_jobs"), ("runner", "verbose", "progress"),
    ("runner", "timeout", "connect_timeout_s"), ("runner", "scheduler", "address"),
    ("runner", "batch", "batch_size"), ("runner", "seed", None), ("evaluator", "tolerance", None),
    ("evaluator", "max_iter", "n_max"), ("evaluator", "iterations", "n_max"), ("evaluator", "tau", None),
    ("evaluator", "tau_f", "tau_f_n"), ("evaluator", "seed_depth", "seed_depth_m"),
    ("model", "radius", "fingertip_radius_m"), ("model", "lambda3", None), ("model", "n", "n_exp"),
    ("model", "mu", None), ("model", "stiffness", None), ("model", "damping", "damping_law"),
    ("pso", "particles", "n_particles"), ("pso", "iterations", "n_iterations"), ("pso", "w", "inertia"),
    ("pso", "seed", None), ("output", "dir", "root"), ("output", "name", "run"),
    ("factors", "mass", "mass_kg"), ("factors", "friction", "mu"), ("factors", "seed", "pso_seed"),
    ("factors", "lambda", None), ("factors", "node", "nodes"), ("factors", "grip", "grip_law"),
    ("factors", "dt", "dt_s"), ("factors", "damping", "damping_law"),
    ("studies", "baseline", "baseline_grid"), ("studies", "test1", "test1_bench"),
    ("studies", "grid", None), ("studies", "test2", "test2_grasp"),
    ("studies", "sensitivty", "sensitivity"), ("studies", "all", None),
    ("kinds", "quasistatic", "quasi_static"), ("kinds", "dynamic", None), ("kinds", "mesh", None),
    ("materials", "silicone", None), ("materials", "foam", "bio_foam"), ("materials", "rubber", None),
    ("planners", "rnd", "random"), ("planners", "centre", "centroid"), ("planners", "greedy", None),
    ("planners", "antipodal_grasp", "antipodal"), ("planners", "ferrari", "ferrari_canny"),
    ("shapes", "cube", "rounded_cube"), ("shapes", "box", None), ("shapes", "cylinder", None),
    ("report formats", "markdown", "md"), ("report formats", "htm", "html"),
    ("report formats", "txt", None), ("report formats", "pdf", None), ("figure formats", "jpg", None),
    ("figure formats", "eps", None), ("units", "in", None), ("units", "inch", None), ("units", "MM", "mm"),
    ("units", "meters", "m"),
]

#: typos the tests pin: (vocabulary, typed, the suggestion the test asserts)
PINNED = [
    ("kinds", "mesh_featurs", "mesh_features"), ("shapes", "spher", "sphere"),
    ("shapes", "sphère", "sphere"), ("backends", "sequentail", "sequential"),
    ("factors", "plannr", "planner"), ("model presets", "nominl", "nominal"),
    ("sensitivity panels", "lamda", "lambda"), ("mesh_resolution panels", "resoluton", "resolution"),
    ("figure formats", "pgn", "png"), ("report formats", "hmtl", "html"), ("units", "mmm", "mm"),
    ("studies", "baselin_grid", "baseline_grid"), ("studies", "smok", "smoke"),
    ("materials", "silicone_rf", "silicone_ref"), ("model", "lambda3", "lambda2"),
    ("runner", "cores", "progress"), ("evaluator", "tau", "tau_f_n"),
    ("params of test3_disturbance", "fractoin", "fraction"),
]


def main() -> None:
    vocab = vocabularies()
    print("rule | single-edit typos: the name alone / among tied / wrong / none | labelled words: "
          "right / wrong (a tie holding the name meant counts right)")
    widest = 0
    for rule in RULES:
        alone = tied = wrong = none = 0
        for names in vocab.values():
            for name in names:
                if len(name) < 3:
                    continue
                for typo in typos(name):
                    if typo in names:
                        continue
                    got = rule(typo, names)
                    widest = max(widest, len(got))
                    alone += got == [name]
                    tied += name in got and len(got) > 1
                    wrong += bool(got) and name not in got
                    none += not got
        good = sum((meant_ in got) if meant_ else not got for v, w, meant_ in LABELLED
                   for got in [rule(w, vocab[v])])
        print(f"{_label(rule)} | {alone} / {tied} / {wrong} / {none} | {good} / {len(LABELLED) - good}")
    print(f"(most names a rule named at once: {widest})")
    print("\ntyped (vocabulary) | pinned by a test, or meant | " + " | ".join(map(_label, RULES)))
    for v, w, meant_ in PINNED + LABELLED:
        print(f"{w} ({v}) | {meant_} | " + " | ".join(" or ".join(r(w, vocab[v])) or "-"
                                                     for r in RULES))


if __name__ == "__main__":
    main()
