"""What a simulation returns: the numbers a rotordynamics user reads (thesis ch. 5).

    r      the rotor amplitude sqrt(x^2 + y^2) (rotating frame; fixed frame: the rotor centre's)
    r_max  its largest value over [0, t_end]
    t_dec  sup{t <= t_end : r(t) >= threshold} (thesis: threshold 1e-3), located on the continuous
           solution; None when r has not settled below the threshold by t_end; 0.0 when r never
           reached it
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import AdbgenError

# Status of one integration: success, an early stop in a target region (sweeps), or a failure.
SUCCESS = "success"
STOPPED = "stopped"
FAILURES = {
    "max_steps": "step limit reached",
    "step_underflow": "step size underflow",
    "nonfinite": "non-finite state or derivative",
    "solver_failure": "solver failure",
    "no_consistent_mode": "no consistent stick/slip mode: a ball can neither stick nor slip (mu_r > mu_s?)",
}


def json_number(v):
    """`json.dumps`'s default: numpy scalars and arrays as plain numbers and lists (non-finite as null)."""
    if hasattr(v, "tolist"):  # numpy scalar or array
        return plain(v.tolist())
    raise TypeError(f"{type(v).__name__} is not JSON")


def plain(obj):
    """`obj` with non-finite floats as null (JSON has no NaN) and numpy values as Python ones."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if hasattr(obj, "tolist"):
        return plain(obj.tolist())
    return obj


class IntegrationError(AdbgenError):
    """A failed, stalled or non-finite integration: names the time it failed at."""

    def __init__(self, status: str, t_fail: float, engine: str, detail: str = ""):
        self.status = status
        self.t_fail = t_fail
        self.engine = engine
        text = f"integration failed at t = {t_fail:.9g} ({FAILURES.get(status, status)}; engine {engine})"
        super().__init__(text + (f": {detail}" if detail else ""))


@dataclass
class Simulation:
    """One trajectory.  `t`, `y` are the accepted steps (y: states on the rows) unless sampled."""

    model: str
    engine: str
    rtol: float
    atol: float
    t_end: float
    threshold: float
    status: str
    t: np.ndarray
    y: np.ndarray
    r_max: float
    t_dec: float | None
    y_end: np.ndarray
    n_rhs: int
    n_steps: int
    wall_s: float  # the integration alone: no imports, no compilation
    state_names: tuple[str, ...] = ()
    parameters: dict = field(default_factory=dict)
    t_fail: float | None = None
    message: str = ""
    picked: dict | None = None  # what the engine ran: the auto engine's choice, the Taylor engine's order
    stuck: tuple[bool, ...] | None = None  # stick/slip models: per ball, whether it ended stuck on the race
    r_end: float | None = None  # stick/slip models: the residual imbalance, r at t_end

    @property
    def ok(self) -> bool:
        return self.status == SUCCESS

    def raise_for_status(self) -> "Simulation":
        if self.status not in (SUCCESS, STOPPED):
            raise IntegrationError(self.status, self.t_fail if self.t_fail is not None else float("nan"),
                                   self.engine, self.message)
        return self

    def to_json(self) -> dict:
        return {
            "model": self.model, "engine": self.engine, "rtol": self.rtol, "atol": self.atol,
            "t_end": self.t_end, "threshold": self.threshold, "status": self.status,
            "r_max": self.r_max, "t_dec": self.t_dec,
            "y_end": {name: float(v) for name, v in zip(self.state_names, self.y_end)},
            "n_rhs": self.n_rhs, "n_steps": self.n_steps, "wall_s": self.wall_s,
            "picked": self.picked if self.picked is not None else {"engine": self.engine},
            "parameters": self.parameters, "t_fail": self.t_fail,
            **({} if self.stuck is None else {"stuck": list(self.stuck), "r_end": self.r_end}),
        }


@dataclass
class Ensemble:
    """Many trajectories (row k: trajectory k).  t_dec is NaN where r did not settle."""

    engine: str
    status: np.ndarray  # str codes
    r_max: np.ndarray
    t_dec: np.ndarray
    y_end: np.ndarray
    t_last: np.ndarray  # time reached (t_end, the early-stop time, or where it failed)
    target: np.ndarray  # index of the target region an early stop reached, else -1
    n_rhs: np.ndarray
    n_steps: np.ndarray
    wall_s: float
    picked: dict | None = None  # the auto engine's choice (engine, tolerances, reason), as Simulation's
    stuck: np.ndarray | None = None  # stick/slip models: (trajectories, balls), whether each ball ended stuck
    r_end: np.ndarray | None = None  # stick/slip models: the residual imbalance, r at t_end (NaN: failed)

    def __len__(self) -> int:
        return len(self.status)
