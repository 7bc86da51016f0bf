"""AUTO-07p driven from Python on a model's emitted files (generated/<model>/auto/).

    continue_one(model, "Omega", p=..., to=0.5)            -> AutoRun: labelled points with stability
    continue_two(model, "Omega", "mu", p=..., to=0.5)      -> AutoCurves: Hopf and fold curves, codim-2 points

The model's auto/ folder is copied to a temporary folder, built and run the way AUTO's own `@r`
does (`make -f $AUTO_DIR/cmds/cmds.make EQUATION_NAME=<model> < c.<model>`; Debian's auto-07p with
gfortran), with the constants file edited for the run (ICP, DS, UZSTOP, and the start through
AUTO's `U` and `PAR` keys when parameters are set); fort.7 and fort.8 are read here (AUTO's Python
reader fails under numpy 2).

Two-parameter curves: the one-parameter run's Hopf (HB) and fold (LP) labels are restarted with
ISW = 2 and the second parameter free, in both directions; along them AUTO reports the
codimension-two points: Bogdanov-Takens (BT), zero-Hopf (ZH, fold-Hopf), generalised Hopf (GH,
Bautin), cusp (CP), and on a Hopf curve a further HB label is a double Hopf point (HH).

For n >= 3 the emitted func carries the regularising term of templates/auto/_family.j2 (the family's
zero eigenvalues moved to -1), so the balanced state is an isolated, regular solution there.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..codegen.compiler import AUTO_DIR, auto_include as header_dir
from .loading import AnalysisError, Model

BIFURCATIONS = {1: "BP", 2: "LP", 3: "HB"}  # |TY| in fort.7 of IPS = 1; 4 regular/UZ, 9 end points
TYPES = {1: "BP", 2: "LP", 3: "HB", 4: "RG", -4: "UZ", 9: "EP", -9: "MX", -1: "BT", -2: "CP", -3: "ZH", -32: "GH",
         5: "LP", 6: "BP", 7: "PD", 8: "TR"}
CODIM2 = {"BT": "Bogdanov-Takens", "CP": "cusp", "ZH": "zero-Hopf", "GH": "generalised Hopf", "HH": "double Hopf"}


class AutoError(AnalysisError):
    """AUTO-07p missing, failed to build, or failed to run."""


def missing_tools() -> list[str]:
    """What running AUTO-07p needs and this machine lacks (empty: all there)."""
    return [what for what, ok in (
        ("auto-07p (cmds/cmds.make)", (AUTO_DIR / "cmds" / "cmds.make").is_file()),
        ("auto-07p (lib/libauto_c.a)", (AUTO_DIR / "lib" / "libauto_c.a").is_file()),
        ("auto-07p (auto_f2c.h)", header_dir() is not None),
        ("gfortran", shutil.which("gfortran") is not None),
        ("gcc", shutil.which("gcc") is not None),
        ("make", shutil.which("make") is not None),
    ) if not ok]


# --- fort.7 / fort.8 -------------------------------------------------------------------------------

@dataclass(frozen=True)
class Point:
    """One continuation step of fort.7."""

    branch: int
    pt: int  # negative: stable
    ty: int  # see TYPES; 0 not printed to fort.8
    label: int
    values: dict  # column title of fort.7 (PAR(1), L2-NORM, U(1), ..., PAR(6)) -> value

    @property
    def stable(self) -> bool:
        return self.pt < 0

    @property
    def kind(self) -> str | None:
        return BIFURCATIONS.get(abs(self.ty))

    @property
    def type(self) -> str:
        return TYPES.get(self.ty, str(self.ty))


def _number(text: str) -> float:
    """Fortran E format; an exponent of three digits may lose its E ('1.7976+308')."""
    if not re.search(r"[eEdD]", text):
        text = re.sub(r"(?<=[0-9.])([+-]\d+)$", r"E\1", text)
    return float(text.replace("D", "E").replace("d", "e"))


def _titles(fields: list[str]) -> list[str]:
    """fort.7 column titles; periodic orbits (IPS = 2) print 'MAX U(1)', two words, joined here."""
    out = []
    for item in fields:
        if out and out[-1] in ("MAX", "MIN"):
            out[-1] += " " + item
        else:
            out.append(item)
    return out


def read_fort7(path: Path) -> list[Point]:
    """Every continuation step of fort.7: lines starting with BR = 0 are headers (the last header
    before the data names its columns: 0 PT TY LAB PAR(1) L2-NORM U(1) ..., or MAX U(1) ... PERIOD
    for periodic orbits); the others are BR PT TY LAB followed by those columns."""
    points, titles = [], None
    for line in Path(path).read_text().splitlines():
        fields = line.split()
        if not fields:
            continue
        if fields[0] == "0":
            if len(fields) > 4 and fields[1:4] == ["PT", "TY", "LAB"]:
                titles = _titles(fields[4:])
            continue
        if titles is None:
            raise AutoError(f"fort.7 data before its column titles: {line!r}")
        br, pt, ty, lab = (int(v) for v in fields[:4])
        values = [_number(v) for v in fields[4:]]
        if len(values) != len(titles):
            raise AutoError(f"fort.7: {len(values)} values for {len(titles)} columns: {line!r}")
        points.append(Point(br, pt, ty, lab, dict(zip(titles, values))))
    return points


def unlabelled_stability_changes(points: list[Point]) -> list[tuple[Point, Point]]:
    """Consecutive steps whose stability differs without a labelled bifurcation at either of them."""
    return [(a, b) for a, b in zip(points, points[1:])
            if a.branch == b.branch and a.stable != b.stable and not (a.kind or b.kind)]


@dataclass(frozen=True)
class Solution:
    """One labelled solution of fort.8: AUTO's scaled time t in [0, 1], u (NTPL x NDIM), PAR(1..NPAR)."""

    label: int
    ty: int
    t: np.ndarray
    u: np.ndarray
    par: np.ndarray


def read_fort8(path: Path) -> list[Solution]:
    """fort.8: per solution a header line of integers (IBR NTOT ITP LAB NFPR ISW NTPL NAR NROWPR NTST
    NCOL NPARX, AUTO-07p 0.9 adds NDIM IPS IPRIV ...) and NROWPR lines: NTPL points (t, U(1..NDIM)),
    then the NFPR free parameter indices, their NFPR derivatives, the direction vector at the NTPL
    points (U only, no t) and the NPARX parameters, all read here as one stream of numbers."""
    lines = Path(path).read_text().splitlines()
    out, i = [], 0
    while i < len(lines):
        if not lines[i].strip():
            i += 1
            continue
        head = [int(v) for v in lines[i].split()]
        _, _, itp, lab, nfpr, _, ntpl, nar, nrowpr, _, _, npar = head[:12]
        tokens = " ".join(lines[i + 1: i + 1 + nrowpr]).split()
        if len(tokens) != ntpl * nar + 2 * nfpr + ntpl * (nar - 1) + npar:
            raise AutoError(f"fort.8: label {lab} has {len(tokens)} numbers, not the layout its header gives")
        values = np.array([_number(v) for v in tokens[: ntpl * nar]]).reshape(ntpl, nar)
        par = np.array([_number(v) for v in tokens[-npar:]])
        out.append(Solution(lab, itp, values[:, 0], values[:, 1:], par))
        i += 1 + nrowpr
    return out


def read_multipliers(path: Path, ndim: int) -> np.ndarray:
    """The Floquet multipliers fort.9 printed last (ISP = 2): ndim complex numbers."""
    rows = re.findall(r"^\s*-?\d+\s+-?\d+\s+Multiplier\s+\d+\s+(\S+)\s+(\S+)\s+Abs\. Val\.", Path(path).read_text(), re.M)
    if len(rows) < ndim:
        raise AutoError(f"no multipliers in {path}")
    return np.array([complex(_number(a), _number(b)) for a, b in rows[-ndim:]])


# --- building and running --------------------------------------------------------------------------

def build_and_run(files: dict[str, str], name: str, workdir: Path, constants_file: str | None = None,
                  timeout: float = 300) -> str:
    """Write `files` into workdir, build and run with AUTO's make runner reading the constants
    c.<name> (or `constants_file`); returns make's output (stdout and stderr, tails)."""
    workdir.mkdir(parents=True, exist_ok=True)
    for filename, text in files.items():
        (workdir / filename).write_text(text)
    env = dict(os.environ, AUTO_DIR=str(AUTO_DIR))
    with open(workdir / (constants_file or f"c.{name}")) as constants:
        r = subprocess.run(["make", "-f", str(AUTO_DIR / "cmds" / "cmds.make"), f"EQUATION_NAME={name}"],
                           stdin=constants, cwd=workdir, env=env, capture_output=True, text=True, timeout=timeout)
    return f"--- stdout\n{r.stdout[-4000:]}\n--- stderr\n{r.stderr[-4000:]}"


def auto_parameter(k: int) -> int:
    """1-based AUTO PAR index of model parameter k (0-based): PAR(11)-PAR(14) are AUTO's."""
    return k + 1 if k < 10 else k + 5


def _split_top(line: str) -> list[str]:
    """Split at commas outside brackets and braces ("ICP = [1, 6], NMX = 5" -> two items)."""
    items, depth, cur = [], 0, ""
    for ch in line:
        depth += ch in "[{("
        depth -= ch in "]})"
        if ch == "," and depth == 0:
            items.append(cur)
            cur = ""
        else:
            cur += ch
    return items + [cur]


def set_constants(text: str, **values) -> str:
    """The constants file with KEY = value replaced (or appended as a line; value None removes the
    key); several keys share a line in the emitted files (NTST = 20, NCOL = 4, ...) and values may be
    lists or dicts."""
    lines = text.splitlines()
    for key, value in values.items():
        for i, line in enumerate(lines):
            if line.lstrip().startswith("#") or "=" not in line:
                continue
            items = _split_top(line)
            keys = [item.split("=", 1)[0].strip() for item in items]
            if key in keys:
                if value is None:
                    del items[keys.index(key)]
                else:
                    items[keys.index(key)] = f"{' ' if keys.index(key) else ''}{key} = {value}"
                lines[i] = ",".join(items).lstrip()
                break
        else:
            if value is not None:
                lines.append(f"{key} = {value}")
    return "\n".join(lines) + "\n"


# fort.7 and fort.8 print every number as ES19.10 (AUTO-07p's WRLINE, WRTSP8): 11 significant digits
PRINTED_RELATIVE = 5e-11


def constant(text: str, key: str) -> float | None:
    """The number a constants file gives KEY (e.g. EPSS), None if it gives none."""
    for line in text.splitlines():
        if line.lstrip().startswith("#") or "=" not in line:
            continue
        for item in _split_top(line):
            k, _, v = item.partition("=")
            if k.strip() == key:
                try:
                    return float(v)
                except ValueError:
                    return None
    return None


def location_tolerance(epss: float, ds: float, ds_max: float) -> float:
    """How far AUTO-07p may place a special point (HB, LP, BP) from the zero of its test function, in
    arclength (with AUTO's unit weights it bounds the parameter's error too): LCSPAE (src/ae.f90) stops its
    secant-Mueller iteration once the next correction |RDS| < EPSS (1 + sqrt|DS DSMAX|), leaving that
    correction untaken."""
    return float(epss) * (1.0 + math.sqrt(abs(ds * ds_max)))


def _plain(v):
    """Python numbers and lists (numpy scalars print as np.float64(...), which AUTO cannot read)."""
    return [_plain(x) for x in v] if isinstance(v, (list, tuple)) else float(v)


def _mapping(d: dict) -> str:
    return "{" + ", ".join(f"{int(k)}: {_plain(v)!r}" for k, v in d.items()) + "}"


class Session:
    """A temporary copy of a model's auto/ folder; each `run` writes a constants file and runs AUTO."""

    def __init__(self, model: Model, keep: Path | None = None, forced: bool = False):
        missing = missing_tools()
        if missing:
            raise AutoError("AUTO-07p cannot run here: missing " + ", ".join(missing) +
                            " (Debian packages auto-07p gfortran gcc make)")
        self.model = model
        self.name = model.name
        src = model.folder / "auto"
        if not (src / f"{self.name}.c").is_file():
            raise AutoError(f"{model.name} has no AUTO files ({src}); regenerate with the 'auto' target")
        if not model.autonomous and not forced:  # `auto_orbits` runs a forced model's periodic-orbit stages
            raise AutoError(f"{model.name} is periodically forced: its AUTO files continue periodic orbits "
                            f"(`auto_orbits.continue_orbit`); this session follows steady states")
        self._tmp = None if keep else tempfile.TemporaryDirectory(prefix="adbgen-auto-")
        self.dir = Path(keep) if keep else Path(self._tmp.name)
        self.dir.mkdir(parents=True, exist_ok=True)
        for f in src.iterdir():
            if f.is_file():
                shutil.copy(f, self.dir / f.name)
        self.base = (self.dir / f"c.{self.name}").read_text()
        self.runs = 0

    def close(self):
        if self._tmp is not None:
            self._tmp.cleanup()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def run(self, **constants) -> tuple[list[Point], list[Solution], str]:
        self.runs += 1
        cfile = f"c.{self.name}.run{self.runs}"
        (self.dir / cfile).write_text(set_constants(self.base, **constants))
        for f in ("fort.7", "fort.8", "fort.9"):
            (self.dir / f).unlink(missing_ok=True)
        log = build_and_run({}, self.name, self.dir, cfile)
        if not (self.dir / f"{self.name}.exe").is_file():
            raise AutoError(f"AUTO-07p build failed for {self.name}:\n{log}")
        if "Unknown AUTO constant" in log or not (self.dir / "fort.7").is_file():
            raise AutoError(f"AUTO-07p did not run:\n{log}")
        points = read_fort7(self.dir / "fort.7")
        solutions = read_fort8(self.dir / "fort.8") if (self.dir / "fort.8").is_file() else []
        return points, solutions, log

    def keep_solutions(self, as_name: str) -> None:
        """fort.8 of the last run as the restart file s.<as_name>."""
        shutil.copy(self.dir / "fort.8", self.dir / f"s.{as_name}")


# --- one and two parameters ------------------------------------------------------------------------

@dataclass
class AutoRun:
    model: Model
    name: str  # the continuation parameter
    points: list[Point]
    solutions: list[Solution]
    p: np.ndarray
    location: float | None = None  # `location_tolerance` of this run (None: not known)

    def column(self) -> str:
        return f"PAR({auto_parameter(self.model.param_names.index(self.name))})"

    def labelled(self) -> list[Point]:
        return [pt for pt in self.points if pt.label > 0]

    def hopf(self) -> list[float]:
        return [pt.values[self.column()] for pt in self.points if pt.kind == "HB"]

    def folds(self) -> list[float]:
        return [pt.values[self.column()] for pt in self.points if pt.kind == "LP"]

    def to_json(self) -> list[dict]:
        m, col = self.model, self.column()
        amp = f"PAR({auto_parameter(m.n_params)})"  # pvls: the rotor amplitude
        by_label = {s.label: s for s in self.solutions}
        out = []
        for pt in self.labelled():
            row = {"label": pt.label, "type": pt.type, self.name: pt.values[col],
                   "stability": "stable" if pt.stable else "unstable", "step": abs(pt.pt)}
            if amp in pt.values:
                row["amplitude"] = pt.values[amp]
            if pt.kind == "HB" and pt.label in by_label:
                period = by_label[pt.label].par[10]
                row["frequency"] = 2 * math.pi / period if period > 0 else None
            if pt.kind is not None and self.location is not None:
                # AUTO's own location error plus the printed digits: a bifurcation point is only this well placed
                row["location_uncertainty"] = self.location + PRINTED_RELATIVE * abs(pt.values[col])
            sol = by_label.get(pt.label)
            if sol is not None:
                row["state"] = dict(zip(m.state_names, map(float, sol.u[0])))
            out.append(row)
        return out


def stages_data(model: Model) -> dict | None:
    """The data the AUTO target writes beside a model's AUTO files (auto/stages.json: the stages, the start
    orbit, the continued parameter's bounds; `codegen.targets.auto.stages_data`), None without them."""
    path = model.folder / "auto" / "stages.json"
    return json.loads(path.read_text()) if path.is_file() else None


def default_stop(model: Model, name: str, start: float) -> float | None:
    """Where the model's own AUTO constants (c.<model>) end a run in `name`: the UZSTOP bound on the side its
    DS points to (e.g. Omega = 0.5 for the thesis models, whose Hopf points lie between 1 and 2.2); None when
    the file does not continue `name` (read from the AUTO files' data, `stages_data`)."""
    data = stages_data(model)
    if name not in model.param_names or data is None or not data.get("uzstop"):
        return None
    uz = data["uzstop"]
    if uz["parameter"] != model.param_names.index(name):
        return None
    lo, hi = uz["bounds"]
    stop = lo if uz["down"] else hi
    return stop if stop != start else None


def _start_constants(model: Model, p: np.ndarray, y: np.ndarray) -> dict:
    """AUTO's U and PAR keys for a start other than stpnt's (PAR: every model parameter)."""
    return {"U": _mapping({i + 1: float(v) for i, v in enumerate(y)}),
            "PAR": _mapping({auto_parameter(k): float(v) for k, v in enumerate(p)})}


def continuation_range(model: Model, name: str, p: np.ndarray, to: float | None) -> tuple[int, float, float]:
    """Parameter `name`'s index, its value in p and where its continuation ends: `to`, by default half the
    start (start - 1 from a start <= 0); one line where the name is unknown or `to` is the start."""
    if name not in model.param_names:
        raise AnalysisError(f"{name!r} is not a parameter of {model.name}; parameters: {', '.join(model.param_names)}")
    k = model.param_names.index(name)
    start = float(p[k])
    to = (0.5 * start if start > 0 else start - 1.0) if to is None else float(to)
    if not math.isfinite(to) or to == start:
        raise AnalysisError(f"--to must differ from the start value {name} = {start:g}")
    return k, start, to


def continue_one(model: Model, name: str, p: np.ndarray | None = None, y: np.ndarray | None = None,
                 to: float | None = None, ds: float = 0.001, ds_max: float = 0.002, nmx: int = 20000,
                 session: Session | None = None) -> AutoRun:
    """Continue the steady state (stpnt's, or y at p) in parameter `name` from its value towards `to`."""
    p = np.array(model.module.START_PARAMETERS if p is None else p, float)
    y = np.array(model.module.START if y is None else y, float)
    k, start, to = continuation_range(model, name, p, to)
    sign = 1.0 if to > start else -1.0
    amp = auto_parameter(model.n_params)
    constants = dict(ICP=f"[{auto_parameter(k)}, {amp}]", IRS=0, ISW=1, DS=sign * ds, DSMAX=ds_max, NMX=nmx,
                     NPR=nmx, UZSTOP=_mapping({auto_parameter(k): [min(start, to), max(start, to)]}),
                     **_start_constants(model, p, y))
    own = session is None
    session = session or Session(model)
    try:
        points, solutions, _ = session.run(**constants)
        epss = constant(session.base, "EPSS")
    finally:
        if own:
            session.close()
    location = None if epss is None else location_tolerance(epss, ds, ds_max)
    return AutoRun(model, name, points, solutions, p, location)


@dataclass
class Curve:
    kind: str  # "hopf" or "fold"
    origin: float  # the one-parameter bifurcation it was started from
    points: list[tuple[float, float]]
    special: list[dict] = field(default_factory=list)
    closed: bool = False  # went round a loop back to its origin
    also_from: list[float] = field(default_factory=list)  # other one-parameter points on this curve


def _cut_loop(points: list[Point], columns: tuple[str, str], origin: tuple[float, float], step: float):
    """The points up to where the curve comes back to its origin (a closed curve), and whether it did.
    AUTO's steps are at most DSMAX long, so a return passes within one step of the origin."""
    far = False
    for i, q in enumerate(points):
        d = math.hypot(q.values[columns[0]] - origin[0], q.values[columns[1]] - origin[1])
        if d > 5 * step:
            far = True
        elif far and d <= 1.01 * step:
            return points[: i + 1], True
    return points, False


def _passes_through(curve: list[tuple[float, float]], origin: tuple[float, float], tol: float = 1e-3) -> bool:
    """Whether the polyline crosses the line name2 = origin[1] within tol of origin[0] (linear interpolation)."""
    for (a0, b0), (a1, b1) in zip(curve, curve[1:]):
        if (b0 - origin[1]) * (b1 - origin[1]) <= 0 and b0 != b1:
            a = a0 + (a1 - a0) * (origin[1] - b0) / (b1 - b0)
            if abs(a - origin[0]) <= tol * max(1.0, abs(origin[0])):
                return True
    return False


@dataclass
class AutoCurves:
    model: Model
    name: str
    name2: str
    one: AutoRun
    curves: list[Curve]
    double_hopf: list[dict] = field(default_factory=list)  # found by `double_hopf_points`

    @property
    def special(self) -> list[dict]:
        """Codimension-two points, each once: a curve through the pitchfork at mu_c retraces itself
        (the mirror copy phi_1 <-> phi_2 of the balanced state), meeting its points twice."""
        out: list[dict] = []
        for i, c in enumerate(self.curves):
            for s in c.special:
                same = [o for o in out if o["type"] == s["type"] and all(
                    abs(o[k] - s[k]) <= 1e-5 * max(1.0, abs(s[k])) for k in (self.name, self.name2))]
                if not same:
                    out.append(s | {"curve": i})
        return out + self.double_hopf

    def to_json(self) -> dict:
        return {"curves": [{"kind": c.kind, "origin": {self.name: c.origin}, "closed": c.closed,
                            "also_from": [{self.name: v} for v in c.also_from],
                            "points": [[a, b] for a, b in c.points]} for c in self.curves],
                "special": self.special}


def continue_two(model: Model, name: str, name2: str, p: np.ndarray | None = None, y: np.ndarray | None = None,
                 to: float | None = None, range2: tuple[float, float] | None = None, range1=None,
                 ds: float = 0.002, ds_max: float = 0.01, nmx: int = 3000) -> AutoCurves:
    """One-parameter run in `name`, then every Hopf point and fold continued in (name, name2)."""
    if name2 not in model.param_names:
        raise AnalysisError(f"{name2!r} is not a parameter of {model.name}; parameters: {', '.join(model.param_names)}")
    if name2 == name:
        raise AnalysisError("--par2 must differ from --par")
    k, k2 = model.param_names.index(name), model.param_names.index(name2)
    with Session(model) as session:
        one = continue_one(model, name, p, y, to, session=session)
        session.keep_solutions(model.name)
        p1 = one.p
        value2 = float(p1[k2])
        lo2, hi2 = range2 if range2 is not None else (0.0, 10 * value2 if value2 > 0 else 1.0)
        lo1, hi1 = range1 if range1 is not None else (min(one.p[k], to if to is not None else 0.5 * one.p[k]),
                                                       max(one.p[k], to if to is not None else 0.5 * one.p[k]))
        a1, a2, amp = auto_parameter(k), auto_parameter(k2), auto_parameter(model.n_params)
        col1, col2 = f"PAR({a1})", f"PAR({a2})"
        curves: list[Curve] = []
        for pt in one.labelled():
            if pt.kind not in ("HB", "LP"):
                continue
            kind = "hopf" if pt.kind == "HB" else "fold"
            origin = (pt.values[one.column()], value2)
            twin = next((c for c in curves if c.kind == kind and _passes_through(c.points, origin)), None)
            if twin is not None:  # the same curve, met again from another point of the one-parameter run
                twin.also_from.append(origin[0])
                continue
            halves = []
            for sign in (1.0, -1.0):
                points, _, _ = session.run(
                    s=repr(model.name), IRS=pt.label, ISW=2, ICP=f"[{a1}, {a2}, {amp}]", DS=sign * ds, DSMAX=ds_max,
                    NMX=nmx, NPR=nmx, UZSTOP=_mapping({a1: [lo1, hi1], a2: [lo2, hi2]}), U=None, PAR=None)
                points, closed = _cut_loop(points, (col1, col2), origin, ds_max)
                halves.append(points)
                if closed:  # a closed curve: one direction went all the way round
                    break
            ordered = list(reversed(halves[1])) + halves[0][1:] if len(halves) == 2 else halves[0]
            curve = Curve(kind, origin[0], [(q.values[col1], q.values[col2]) for q in ordered],
                          closed=len(halves) == 1)
            for q in ordered:
                code = TYPES.get(q.ty)
                if kind == "hopf" and code == "HB":
                    code = "HH"  # a second pair on the imaginary axis along a Hopf curve
                if code in CODIM2 and q.label > 0:
                    curve.special.append({"type": code, "name": CODIM2[code], name: q.values[col1],
                                          name2: q.values[col2]})
            curves.append(curve)
    return AutoCurves(model, name, name2, one, curves)


# --- double Hopf points: where two Hopf curves (or one curve with itself) cross ----------------------

def _crossings(a: np.ndarray, b: np.ndarray, same: bool, min_angle: float = 1e-2) -> list[tuple[float, float]]:
    """Proper intersections of the polylines a and b (k x 2 each); with same = True, of a with itself
    (segments at least two apart).  Nearly parallel segments (a curve retracing itself) are skipped."""
    out = []
    p, r = a[:-1], a[1:] - a[:-1]
    q, s = b[:-1], b[1:] - b[:-1]
    for i0 in range(0, len(p), 256):
        P, R = p[i0:i0 + 256, None, :], r[i0:i0 + 256, None, :]
        cross = R[..., 0] * s[None, :, 1] - R[..., 1] * s[None, :, 0]
        qp = q[None, :, :] - P
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (qp[..., 0] * s[None, :, 1] - qp[..., 1] * s[None, :, 0]) / cross
            u = (qp[..., 0] * R[..., 1] - qp[..., 1] * R[..., 0]) / cross
        norms = np.linalg.norm(R, axis=-1) * np.linalg.norm(s, axis=-1)[None, :]
        ok = (t >= 0) & (t < 1) & (u >= 0) & (u < 1) & (np.abs(cross) > min_angle * norms)
        if same:
            ii, jj = np.indices(ok.shape)
            ok &= (jj - (ii + i0)) >= 2
        for i, j in zip(*np.nonzero(ok)):
            out.append(tuple(p[i0 + i] + t[i, j] * r[i0 + i]))
    return out


def double_hopf_points(model: Model, curves: list[Curve], p: np.ndarray, name: str, name2: str, steady_at,
                       tol: float = 1e-9) -> list[dict]:
    """Double Hopf points (HH) among the crossings of Hopf curves, confirmed and refined on the
    analysis layer's transverse spectrum: two pairs with different frequencies on the imaginary axis.
    `steady_at(p)` returns the followed steady state at parameters p (AUTO-07p 0.9 does not flag them)."""
    from scipy.optimize import root

    from .steady import analyse

    k1, k2 = model.param_names.index(name), model.param_names.index(name2)
    hopf = [np.array(c.points) for c in curves if c.kind == "hopf" and len(c.points) > 2]
    candidates = []
    for i, a in enumerate(hopf):
        for j, b in enumerate(hopf[i:], start=i):
            candidates += _crossings(a, b, same=(i == j))

    def spectrum(x):
        q = np.array(p, float)
        q[k1], q[k2] = x
        return analyse(model, q, steady_at(q)).transverse

    found: list[dict] = []
    for c in candidates:
        try:
            ev = spectrum(c)
        except AnalysisError:
            continue
        pairs = ev[(ev.imag > 1e-6)]
        pairs = pairs[np.argsort(np.abs(pairs.real))][:2]
        if len(pairs) < 2 or abs(pairs[0].imag - pairs[1].imag) < 1e-4 or np.max(np.abs(pairs.real)) > 1e-3:
            continue  # a curve crossing its own retrace, or one pair only

        def g(x, w=(pairs[0].imag, pairs[1].imag)):
            e = spectrum(x)
            e = e[e.imag > 1e-6]
            return [e[np.argmin(np.abs(e.imag - wk))].real for wk in w]
        sol = root(g, np.array(c), tol=1e-14)
        if not sol.success or np.max(np.abs(g(sol.x))) > tol:
            continue
        x = [float(v) for v in sol.x]
        if any(abs(f[name] - x[0]) < 1e-7 and abs(f[name2] - x[1]) < 1e-7 for f in found):
            continue
        ev = spectrum(sol.x)
        w = sorted(float(z.imag) for z in ev[(ev.imag > 1e-6)][np.argsort(np.abs(ev[(ev.imag > 1e-6)].real))][:2])
        found.append({"type": "HH", "name": CODIM2["HH"], name: x[0], name2: x[1], "frequencies": w})
    return found
