"""The `auto` engine (the default): per requested tolerance, the engine and settings that reached the
tolerance fastest in the work-precision measurements of `adbgen bench auto` (`TABLE`, package data;
the benchmark rewrites it).  It runs the chosen engine and says what it picked (`picked`, in
`adbgen simulate --json`).

The table's rows: {"rtol": R, "engine": E, "rtol_run": r, "order": p, "step_factor": f}: the
candidate admissible at R (a Taylor step aimed at R/10 or less, `benchmarks.engine_table.admissible`) and
ending within R on the held-in check scenes (`benchmarks.engine_table.passes_check`, issue 35) that reached an
error of at most R (relative to the state's size, see `adbgen bench auto`) fastest, per measured problem
(`by_problem`: {label: {"roles", "rows"}}, the problem's model's kinds of coordinate, its
self-description's STATE_ROLES each once, sorted) and jointly (`rows`, fastest over every problem);
a model takes the rows of the problem with the most kinds of coordinate that the model all has (its
own kinds, or some of them: a model with a spin angle besides takes the rows of the problem without
one), and the joint rows where no problem's kinds are all among its own.  A row is run as engine E at rtol r (atol scaled by the same factor) with, for the Taylor engine,
order p and step factor f.  A requested rtol takes the row of the largest R at or below it (so the
measured error is at most the requested rtol); tighter than every row: the tightest row.  A model without a Taylor series (the `taylor` target
skips a model whose kernel has a function without a recurrence) runs on `FALLBACK` (CyRK's DOP853) at
the requested tolerance, `picked` saying why.

Ensembles without r_max/t_dec (`run_many(..., measures=False)`: the sweeps' attractor labels, basin maps)
run on `ENSEMBLE`, the DOP853 step on SIMD lanes, at the requested tolerance (as the sweeps ran before the
auto engine): on the basin map of `adbgen bench ensemble` it integrates several times as many trajectories
per CPU-second as the single-trajectory pick of the table (benchmarks/ensemble.json, the `auto` and
`rk-dop853-batch` rows).  `taylor-batch-inf` (heyoka's step rule and order in the emitted series) is
faster on that map (2026-11-27 23:55 UTC: 1365 against 885 trajectories per CPU-s, labels off a
converged map at 17 against 21 points) but controls each step in the state's inf norm, holding every
component only to the largest one's scale: in an SI scene (metres beside radians) the rotor's
displacement would go uncontrolled, so the sweeps keep the per-component error control of every other
engine.  A model without a lanes header
(the lanes target skips rhs that branch) and ensembles with measures take the table's pick as a single
run does.
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

from ..loading import AnalysisError
from .rk import lanes_source

TABLE = Path(__file__).resolve().parent / "auto_table.json"
FALLBACK = "cyrk-dop853"  # for a model without a Taylor series (`<model>_taylor.c`)
ENSEMBLE = "rk-dop853-batch"  # for ensembles without measures, where the model has a lanes header


def _has_series(model) -> bool:
    return (Path(model.folder) / f"{model.name}_taylor.c").is_file()


@lru_cache(maxsize=4)
def load_table(path: str = str(TABLE)) -> dict:
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, ValueError) as exc:
        raise AnalysisError(f"the auto engine's table {path} is unreadable ({exc}); run `adbgen bench auto`") from None
    rows = sorted(data.get("rows", []), key=lambda r: r["rtol"])
    if not rows:
        raise AnalysisError(f"the auto engine's table {path} has no rows; run `adbgen bench auto`")
    return {**data, "rows": rows}


def table_rows(table: dict, roles=None) -> list[dict]:
    """The rows for a model whose states play `roles` (its STATE_ROLES; None: unknown): those of the measured
    problem with the most kinds of coordinate all among the model's, else the joint rows."""
    kinds = set(roles or ())
    within = [(-len(p["roles"]), label) for label, p in table.get("by_problem", {}).items()
              if p["rows"] and set(p["roles"]) <= kinds]
    return table["by_problem"][min(within)[1]]["rows"] if within else table["rows"]


def table_choice(rtol: float, roles=None, path: str | None = None) -> dict:
    """The table's row for a requested rtol and a model's state roles (`table_rows`): the row of the
    largest tolerance at or below rtol (tighter than every row: the tightest row)."""
    table = load_table(path or str(TABLE))
    rows = sorted(table_rows(table, roles), key=lambda r: r["rtol"])
    fitting = [r for r in rows if r["rtol"] <= rtol * (1 + 1e-9)]
    return dict(fitting[-1] if fitting else rows[0])


class AutoEngine:
    """Picks an engine per tolerance from `TABLE` (see the module docstring)."""

    name = "auto"
    description = "the engine and settings that reached each tolerance fastest (adbgen bench auto's table)"
    symmetric = True  # every engine the table may pick is (taylor, cyrk-*); tested
    native_events = True

    def __init__(self, engines: dict, table: str | None = None):
        self._engines = engines
        self._table = table

    def table(self) -> dict:
        return load_table(self._table or str(TABLE))

    def choice(self, rtol: float, roles=None) -> dict:
        """The table's row for a requested rtol and a model's state roles (see the module docstring)."""
        return table_choice(rtol, roles, self._table)

    def picked(self, rtol: float, atol: float, model=None):
        """(engine object, rtol, atol, picked record) to run for a requested tolerance (and model)."""
        row = self.choice(rtol, getattr(getattr(model, "module", None), "STATE_ROLES", None))
        if "order" in row and model is not None and not _has_series(model):
            # a model the taylor target skipped (no recurrence for one of its functions): the RK engine
            # that was the default before, at the requested tolerance, and the reason in `picked`
            row = {"engine": FALLBACK, "rtol": rtol, "reason": f"{model.name} has no Taylor series"}
        name = row["engine"]
        if name not in self._engines or name == self.name:
            raise AnalysisError(f"the auto engine's table picks {name!r}, which is not an engine here")
        eng = self._engines[name]
        scale = row.get("rtol_run", rtol) / rtol
        record = {"engine": name, "rtol": rtol * scale, "atol": atol * scale}
        if "reason" in row:
            record["reason"] = row["reason"]
        if "order" in row:
            from .taylor import TaylorEngine

            eng = TaylorEngine(name, eng.description, table=[(0.0, int(row["order"]), float(row["step_factor"]))])
            record.update(order=int(row["order"]), step_factor=float(row["step_factor"]))
        return eng, rtol * scale, atol * scale, record

    def run(self, model, p, y0, t_end, rtol, atol, threshold, max_steps, keep_trajectory=True, samples=2001):
        eng, r, a, record = self.picked(rtol, atol, model)
        out = eng.run(model, p, y0, t_end, r, a, threshold, max_steps, keep_trajectory=keep_trajectory,
                      samples=samples)
        return {**out, "picked": record}

    def picked_many(self, rtol: float, atol: float, model=None, measures: bool = True):
        """As `picked`, for an ensemble: `ENSEMBLE` where no measures are asked and the model has lanes."""
        has_lanes = model is not None and lanes_source(model) is not None
        if not measures and ENSEMBLE in self._engines and has_lanes:
            return self._engines[ENSEMBLE], rtol, atol, {
                "engine": ENSEMBLE, "rtol": rtol, "atol": atol,
                "reason": "an ensemble without r_max/t_dec: the SIMD batch engine (adbgen bench ensemble)"}
        return self.picked(rtol, atol, model)

    def run_many(self, model, P, Y0, t_end, rtol, atol, threshold, max_steps, threads=None, check_dt=0.0,
                 targets=(), measures=True):
        eng, r, a, record = self.picked_many(rtol, atol, model, measures)
        out = eng.run_many(model, P, Y0, t_end, r, a, threshold, max_steps, threads=threads, check_dt=check_dt,
                           targets=targets, measures=measures)
        return {**out, "picked": record}


__all__ = ["AutoEngine", "ENSEMBLE", "FALLBACK", "TABLE", "load_table", "table_choice", "table_rows"]
