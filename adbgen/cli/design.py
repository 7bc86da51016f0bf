"""`adbgen design`: the parameters that keep the balancing state stable over a speed range, for every
imbalance up to a maximum (issue 39; the analysis in adbgen/analysis/design.py, the output in
adbgen/analysis/design_report.py, the page docs/design.md).

    adbgen design SCENE --range omega=LOW:HIGH [--range NAME=LOW:HIGH ...] --imbalance LOW:HIGH
                 --vary NAME=LOW:HIGH [--vary ...] [--set NAME=VALUE ...]
                 [--objective margin|t_dec|r_max-run-up|residual] [--runs MODEL|SCENE] [--run-set NAME=VALUE ...]
                 [--run-time T] [--residual-starts N] [--residual-quantile Q] [--residual-target R]
                 [--residual-measure NAME]
                 [--workers N] [--out DIR] [--json]

SCENE: a generated model's name, a model folder, or a scene file (TOML).
"""

from __future__ import annotations

import shlex
import sys
from pathlib import Path

from .arguments import Commands, _emit_json, quantity_pair

command = Commands()
register = command.register

BEST_KEYS = ("the varied values", "balancing_state_exists", "capacity", "capacity_slack", "feasible", "margin",
             "decay_rate", "margin_uncertainty", "marginal", "worst_point", "leading_eigenvalue", "unstable_at",
             "failures", "box_samples", "orbit_period", "leading_multiplier")
JSON_FIELDS = {"model": "", "balancing_state": "", "objective": "", "box": "", "imbalance_parameter": "",
               "imbalance_floor": "", "varied": "", "method": "(interval | chart | optimiser)", "feasible": "",
               "feasible_intervals": "", "boundaries": "[{at, kind, worst_point, bracket}]",
               "best": "{" + ", ".join(BEST_KEYS) + "}", "active_boundary": "",
               "sensitivity": "[{parameter, dmargin, dmargin_finite_difference, agree, kink, direction_to_boundary, "
                              "room_linear, method (a forced model's: finite differences only)}]", "chart": "",
               "resolution": "", "evaluations": "",
               "evaluations_resumed": "(of the evaluations, those read back from --out's journal)",
               "objective_runs": "(--objective t_dec: [{design, point, start, status, t_end, threshold, t_dec, r_max, r_end, "
                                 "settled}]; r_max-run-up: [{design, point, run_model, mapped, status, t_end, "
                                 "threshold, r_max, t_dec, start}]; residual: [{design, point, run_model, mapped, "
                                 "residual_quantile, quantile, starts, residuals, failed, at_rest, undecided, "
                                 "meets_target}])", "verification": "(the same run keys, at the box's corners)",
               "verification_start": "",
               "verification_run_up": "(the chosen design's run-up on --runs (default the design's model) where its speed law "
                                      "is a schedule: {design, point, run_model, mapped, start, status, t_end, schedule_end, "
                                      "threshold, r_max, t_dec, r_end, settled}; null without one)",
               "verification_run_up_note": "(one line: why there is no run-up; null with one)", "not_covered": "",
               "boundary_types": "{certified: [...], not_certified: [...], scope}",
               "balls": "(--balls: [{n, feasible, best, margin, t_dec, objective_value, margin_uncertainty, capacity, "
                        "limit}])", "chosen_balls": "(--balls)",
               "balls_choice": "(--balls: {objective, value, method, ranking, chosen, runner_up, decided, why})",
               "files": "(with --out)",
               "residual": "(--objective residual: {run_model, kept, unit, starts, seed, quantile, target, "
                           "chosen_quantile, designs_run, designs_decided, at_rest, undecided, failed, note, measure}; null "
                           "otherwise)"}
JSON_KEYS = ", ".join(k + (f" {v}" if v else "") for k, v in JSON_FIELDS.items())


@command("design", "design a balancer: the varied parameters that keep the balancing state stable over a speed "
                   "range for every imbalance up to a maximum (certified scans; the best design by its margin)")
def _add_design(p) -> None:
    p.add_argument("scene", help="a generated model's name (one of generated/), a model folder, or a scene file (TOML)")
    p.add_argument("--range", action="append", default=[], metavar="NAME=LOW:HIGH", dest="ranges",
                   help="an operating range the design must be stable over (repeatable): omega (the model's speed "
                        "parameter) or any parameter by name; LOW = HIGH fixes it; values with units allowed "
                        "(omega=3000rpm:6000rpm)")
    p.add_argument("--imbalance", metavar="LOW:HIGH",
                   help="the imbalance interval (the model's eccentricity parameter), e.g. 0:0.01; the design must "
                        "balance every imbalance in it (default: the model's value, fixed)")
    p.add_argument("--vary", action="append", default=[], metavar="NAME=LOW:HIGH", required=True,
                   help="a design parameter and its interval (repeatable): one gives the feasible interval(s) and "
                        "their ends, two a chart, more an optimiser (scipy COBYLA)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", help="a fixed parameter")
    p.add_argument("--tie", action="append", default=[], metavar="NAME=VARIED",
                   help="parameter NAME takes the value of VARIED, the name of a --vary parameter: a name, not an "
                        "expression (repeatable), e.g. --tie c_bt=c_bb (both races' ball damping), --tie m_2=m_1 "
                        "(the balls alike); continue's --tie takes NAME=EXPR")
    p.add_argument("--balls", metavar="N1..N2",
                   help="with a scene file: design for each ball count from N1 to N2 (the scene's n replaced; its "
                        "per-ball values must be given once, not as lists) and choose the best count by the objective")
    p.add_argument("--objective", default="margin", choices=("margin", "t_dec", "r_max-run-up", "residual"),
                   help="what chooses the best design: margin (the largest worst decay rate over the box), t_dec "
                        "(the shortest t_dec at the operating point), r_max-run-up (the smallest r_max through the "
                        "run model's run-up: --runs, a scene whose [speed] law is a schedule) or residual (the "
                        "smallest quantile (--residual-quantile, 0.9) over starts (--residual-starts, 16) of the residual "
                        "imbalance at rest, stick-slip runs on --runs, a scene with static_friction; without --runs a "
                        "SCENE file with static_friction is designed on its frictionless twin and run as it is; refused "
                        "where there is no stick phase); the last three among at most 25 feasible designs assessed")
    p.add_argument("--runs", metavar="MODEL|SCENE",
                   help="the model the r_max-run-up or residual runs use (default: the design's own): parameters it "
                        "shares by name take the design's values, its speed parameter the operating speed")
    p.add_argument("--run-set", action="append", default=[], metavar="NAME=VALUE",
                   help="a fixed parameter of the --runs model (its speed law's or friction's), e.g. t_ramp=100")
    p.add_argument("--run-time", type=float, metavar="T",
                   help="r_max-run-up: the run's time after the schedule; residual: the run's length (default: "
                        "the default run at the final speed, 4000 / speed, or 1000 time units)")
    p.add_argument("--residual-starts", type=int, metavar="N",
                   help="residual: the starts per design (the rotor at rest, the ball angles uniform at random, seeded; "
                        "default 16)")
    p.add_argument("--residual-quantile", type=float, metavar="Q",
                   help="residual: the quantile over the starts that chooses the design (0 < Q <= 1, default 0.9)")
    p.add_argument("--residual-target", metavar="R",
                   help="residual: the largest residual imbalance accepted (the quantile's value, in the scene's units "
                        "of length, e.g. 1e-5 or 0.01mm); no design reaching it: infeasible")
    p.add_argument("--residual-measure", metavar="NAME",
                   help="residual: which of the run model's measures at the run's end is the residual imbalance "
                        "(default: the one the model names, its RESIDUAL_MEASURE: r in one plane, A, which also sees "
                        "the tilt, in two)")
    p.add_argument("--workers", type=int, metavar="N",
                   help="threads of the local Dask cluster the runs go to (default: the cores available)")
    p.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar on stderr (none either with --json or without a terminal)")
    p.add_argument("--no-verify", dest="verify", action="store_false",
                   help="skip the verification runs of the chosen design at the box's corners")
    p.add_argument("--out", help="folder: design.json, report.md (a one-page report), design.png, and "
                                 "design-journal.jsonl (every design assessed and every finished run: a killed design run "
                                 "again with the same arguments and --out reads them back and computes only the rest)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout; keys: " + JSON_KEYS)
    p.set_defaults(fn=run_design)


def _interval(text: str, option: str, unit: str) -> tuple[float, float]:
    from ..analysis.loading import AnalysisError

    a, b = quantity_pair(text, unit, option, "LOW:HIGH", (option, option))
    if a > b:
        raise AnalysisError(f"{option}: LOW {a:g} is above HIGH {b:g}")
    return a, b


def _named(items, option: str, model) -> list:
    from ..analysis.design import Axis
    from ..analysis.loading import AnalysisError
    from ..analysis.units import DOMAINS, domains, units

    unit, domain = units(model).params, domains(model)
    out = []
    for item in items:
        name, sep, rest = str(item).partition("=")
        name = name.strip()
        if not sep or not name:
            raise AnalysisError(f"{option}: expected NAME=LOW:HIGH, got {item!r}")
        if name not in model.param_names and name.lower() in ("omega", "speed") and "speed" in model.scales:
            name = model.scales["speed"]  # omega: the model's speed parameter, whatever its name
        if name not in model.param_names:
            raise AnalysisError(f"{option}: {name!r} is not a parameter of {model.name}; parameters: "
                                f"{', '.join(model.param_names)}")
        axis = Axis(name, *_interval(rest, f"{option} {name}", unit[name]))
        test, why = DOMAINS.get(domain.get(name, "real"), DOMAINS["real"])
        if not (test(axis.low) and test(axis.high)):
            raise AnalysisError(f"{option} {name}: {why} (the derivation's assumption), got {axis.low:g}:{axis.high:g}")
        out.append(axis)
    return out


def _is_scene_file(text: str) -> bool:
    """SCENE names a scene file (not a generated model's name or a model folder)."""
    path = Path(text)
    return path.suffix == ".toml" or path.is_file()


def _load_scene(text: str):
    from ..analysis.loading import load_model

    if _is_scene_file(text):
        return load_model(scene=text)
    return load_model(text)


def _ball_counts(text: str) -> list[int]:
    from ..analysis.loading import AnalysisError

    low, sep, high = str(text).replace(":", "..").partition("..")
    try:
        a, b = int(low), int(high)
    except ValueError:
        raise AnalysisError(f"--balls: expected N1..N2 (whole numbers), got {text!r}") from None
    if not sep or not 1 <= a <= b or b > 64:
        raise AnalysisError(f"--balls: expected 1 <= N1 <= N2 <= 64, got {text!r}")
    return list(range(a, b + 1))


def _scene_with_balls(scene: str, n: int, folder: Path) -> str:
    """A copy of the scene file with its ball count n (one line `n = ...` replaced); refused where a per-ball
    value is a list (its length would have to change with n)."""
    import re
    import tomllib

    from ..analysis.loading import AnalysisError

    text = Path(scene).read_text()
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise AnalysisError(f"scene file {scene}: {exc}") from None
    lists = sorted(k for k, v in data.items() if isinstance(v, list) and len(v) == data.get("n"))
    if lists:
        raise AnalysisError(f"--balls: the scene gives {', '.join(lists)} ball by ball (a list of n values): give one "
                            "value for every ball to vary the count")
    new, count = re.subn(r"(?m)^n\s*=\s*\d+", f"n = {n}", text)
    if count != 1:
        raise AnalysisError(f"--balls: scene file {scene} has no single line `n = ...` to change")
    path = folder / f"n{n}.toml"
    path.write_text(new)
    return str(path)


FRICTION_KEYS = ("rolling_resistance", "static_friction")  # a scene's friction (docs/friction.md, docs/scenes.md)


def _frictionless_scene(scene: str, folder: Path) -> str | None:
    """The scene file's frictionless twin for `--objective residual` (None where the scene has no stick phase):
    the same scene with `rolling_resistance = 0.0` and no `static_friction`, so its model keeps the stiction
    model's frame and parameters (the rotating frame in the scene's own units, friction in slip at mu_r = 0, the
    frictionless model by the check `friction, zero limit`) and has the closed-form balancing state the design
    needs.  The twin's text depends on the scene's only: the scene cache generates it once."""
    import re
    import tomllib

    from ..analysis.loading import AnalysisError

    path = Path(scene)
    if path.suffix != ".toml" and not path.is_file():
        return None
    text = path.read_text()
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise AnalysisError(f"scene file {scene}: {exc}") from None
    if "static_friction" not in data:
        return None
    new = re.sub(r"(?m)^static_friction\s*=.*\n?", "", text)
    new = re.sub(r"(?m)^rolling_resistance\s*=.*$", "rolling_resistance = 0.0", new)
    try:
        twin = tomllib.loads(new)
    except tomllib.TOMLDecodeError:
        twin = {}
    if "static_friction" in twin or twin.get("rolling_resistance") != 0.0 or \
            {k: v for k, v in twin.items() if k not in FRICTION_KEYS} != {k: v for k, v in data.items() if k not in FRICTION_KEYS}:
        raise AnalysisError(f"--objective residual: scene file {scene}: its friction keys ({', '.join(FRICTION_KEYS)}) "
                            "must each be one line `key = value` to make its frictionless twin")
    out = folder / f"{path.stem}-frictionless.toml"
    out.write_text(new)
    return str(out)


def _by_balls(args, counts: list[int]):
    """(the chosen count's design, one row per count, the chosen count, balls_choice): a design per ball count,
    the best by the objective (analysis/design_balls.py)."""
    import tempfile

    from ..analysis import design_balls

    rows, designs = [], {}
    with tempfile.TemporaryDirectory(prefix="adbgen-design-") as tmp:
        for n in counts:
            designs[n] = _one_design(args, *_models(args, _scene_with_balls(args.scene, n, Path(tmp)), Path(tmp)))
            rows.append(design_balls.row(n, designs[n], args.objective))
    chosen, choice = design_balls.choose(rows, args.objective)
    return designs[chosen if chosen is not None else counts[-1]], rows, chosen, choice


def _models(args, scene: str, folder: Path):
    """(the design's model, the run model or None, the run model's own parameters {name: value}): with
    `--objective residual`, no --runs and a scene file with a stick phase, the design is made on the scene's
    frictionless twin (`_frictionless_scene`) and the residual runs on the scene's own stiction model; the two
    share the scene's parameters by name and units (so the design's values map to the runs one to one), and
    the parameters the twin changed (its friction: the values that differ between the two models' defaults)
    keep the run model's own values."""
    if args.objective == "residual" and args.runs is None:
        twin = _frictionless_scene(scene, folder)
        if twin is not None:
            model, runs = _load_scene(twin), _load_scene(scene)
            mine = dict(zip(model.param_names, map(float, model.params())))
            own = {n: float(v) for n, v in zip(runs.param_names, runs.params()) if n in mine and mine[n] != float(v)}
            return model, runs, own
    return _load_scene(scene), None, {}


def _one_design(args, model, runs=None, own=None):
    from ..analysis import design_transients
    from ..analysis.design import Axis, Problem, solve
    from ..analysis.design_runs import Journal, check_runs, run_params
    from ..analysis.loading import AnalysisError
    from ..analysis.units import assignments, params, units
    from ..progress import wanted

    if "eccentricity" not in model.scales:  # before the arguments are read: the imbalance needs it
        raise AnalysisError(f"{model.name} names no eccentricity parameter (SCALES): no imbalance to design for")
    values = assignments(args.set, "--set", units(model).params)
    base = params(model, values)
    box = _named(args.ranges, "--range", model)
    ecc = model.scales["eccentricity"]
    if args.imbalance is not None:
        lo, hi = _interval(args.imbalance, "--imbalance", units(model).params[ecc])
        if lo < 0:
            raise AnalysisError(f"--imbalance: must be >= 0, got {lo:g}")
        box.append(Axis(ecc, lo, hi))
    varied = _named(args.vary, "--vary", model)
    ties = {}
    for item in args.tie:
        name, sep, source = str(item).partition("=")
        if not sep or not name.strip() or not source.strip():
            raise AnalysisError(f"--tie: expected NAME=VARIED, got {item!r}")
        ties[name.strip()] = source.strip()
    problem = Problem(model, base, box, varied, ties=ties)
    if runs is None:
        runs = _load_scene(args.runs) if args.runs is not None else model
    # the run model's own values (a frictionless twin's friction), then --run-set's: neither taken from the design
    run_set = {**(own or {}), **assignments(args.run_set, "--run-set", units(runs).params)}
    residual = _residual_options(args, runs)
    if args.objective in ("r_max-run-up", "residual"):
        check_runs(args.objective, runs, residual.get("measure"))  # before the design's scans: refused at once
        run_params(problem, runs, [a.low for a in varied], {}, run_set)
    if args.workers is not None and args.workers < 1:
        raise AnalysisError(f"--workers: expected a whole number >= 1, got {args.workers}")
    journal = Journal(Path(args.out) if args.out is not None else None)
    how = {"workers": args.workers, "progress": args.progress and wanted(json=args.json)}
    # the designs' certified scans: batches on the local Dask cluster, every verdict journalled (issue 39 item 5)
    problem.journal, problem.parallel, problem.workers, problem.progress = journal, True, how["workers"], how["progress"]
    design = solve(problem)
    if args.objective == "t_dec":
        design_transients.by_t_dec(design, journal, **how)
    elif args.objective in ("r_max-run-up", "residual"):
        design_transients.by_runs(design, args.objective, runs, journal, run_time=args.run_time, run_set=run_set,
                                  **residual, **how)
    if args.verify and design.best is not None and design.best.feasible:
        design.verification = design_transients.verify(problem, design.best.design, journal, **how)
        design.verification_run_up, design.verification_run_up_note = design_transients.verify_run_up(
            problem, design.best.design, runs, journal, run_time=args.run_time, run_set=run_set, **how)
    return design


def _residual_options(args, runs) -> dict:
    """by_runs' residual settings from --residual-starts/-quantile/-target (refused in one line where out of range
    or given with another objective)."""
    from ..analysis.loading import AnalysisError
    from ..analysis.units import quantity, units

    given = [o for o, v in (("--residual-starts", args.residual_starts), ("--residual-quantile", args.residual_quantile),
                            ("--residual-target", args.residual_target), ("--residual-measure", args.residual_measure))
             if v is not None]
    if args.objective != "residual":
        if given:
            raise AnalysisError(f"{given[0]}: only with --objective residual")
        return {}
    out = {}
    if args.residual_measure is not None:
        out["measure"] = args.residual_measure
    if args.residual_starts is not None:
        if args.residual_starts < 1:
            raise AnalysisError(f"--residual-starts: expected a whole number >= 1, got {args.residual_starts}")
        out["starts"] = args.residual_starts
    if args.residual_quantile is not None:
        if not 0 < args.residual_quantile <= 1:
            raise AnalysisError(f"--residual-quantile: expected 0 < Q <= 1, got {args.residual_quantile:g}")
        out["quantile"] = args.residual_quantile
    if args.residual_target is not None:
        unit = units(runs).length  # r's unit: the scene's length (m in SI), 1 in a dimensionless model
        out["target"] = quantity(args.residual_target, unit, "--residual-target")
        if not out["target"] >= 0:
            raise AnalysisError(f"--residual-target: expected a value >= 0, got {args.residual_target}")
    return out


def run_design(args) -> int:
    from ..analysis import design_report
    from ..analysis.loading import AnalysisError
    from ..outputs import output_folder

    if args.out is not None:
        output_folder(args.out, "--out")
    counts = _ball_counts(args.balls) if args.balls is not None else None
    if counts is not None:
        if not Path(args.scene).is_file():
            raise AnalysisError("--balls needs a scene file (TOML): a generated model's ball count is fixed")
        design, rows, chosen, choice = _by_balls(args, counts)
    else:
        import tempfile

        with tempfile.TemporaryDirectory(prefix="adbgen-design-") as tmp:
            design = _one_design(args, *_models(args, args.scene, Path(tmp)))
        rows, chosen, choice = None, None, None
    out = design_report.to_json(design, args.objective)
    if rows is not None:
        out.update({"balls": rows, "chosen_balls": chosen, "balls_choice": choice})
    command = "adbgen design " + shlex.join(sys.argv[2:]) if sys.argv[1:2] == ["design"] else "adbgen design"
    if args.out is not None:
        out["files"] = design_report.write(design, Path(args.out), command, args.objective, rows, choice,
                                           scene=args.scene if _is_scene_file(args.scene) else None)
    if args.json:
        _emit_json(out)
    else:
        print(design_report.report(design, command, args.objective, rows, choice).split("![design]")[0].rstrip())
    return 0
