"""How a trajectory's tail approaches its end: the rate of approach of the rotor's amplitude r (issue 34).

    tail(t, r)          -> Tail: r's envelope over the tail, fitted as an exponential and as a power of t
    windings(t, angles) -> whole turns each ball's angle makes over the tail

A run that has not reached a state the classifier can name by t_end is carried on and decided by how r
approaches its limit (`attractors.Classifier.decide`).  The envelope is r's largest value in each of
`segments` equal stretches of the tail, at the time it is reached (one value per stretch: an oscillation
of r inside a stretch does not count, only how its top moves).  Two laws are fitted to the envelope by least squares:

    exponential   ln r = a + lam t          (a hyperbolic state: r ~ exp(lam t), lam < 0)
    algebraic     ln r = b - k ln t         (a non-hyperbolic state: r ~ t^-k, as the thesis' Fig. 5.14(d),
                                             n = 4 at mu = mu_c, where r falls like t^-1)

Criterion (stated once, used by the classifier and its tests):

* decays: r's envelope falls over the tail by more than DROP (ln) and falls between at least
  MONOTONE of its consecutive stretches;
* its kind is the law with the smaller root-mean-square residual in ln r; "algebraic" only where that
  residual is below half the exponential's (an algebraic decay over [T, 2T] departs from the best
  exponential by a few hundredths in ln r, an exponential from the best power law likewise, so a clear
  factor separates them; where they are within it the decay is called exponential, and the exponent
  of both fits is reported);
* grows: the envelope ends more than DROP above where it started;
* band: the envelope moves by less than BAND (ln) over the tail (a cycle, or a state not yet left);
* otherwise irregular (it rises and falls: a run still drifting).

The time t of the fits is the model's time from the trajectory's start (the classifier passes the
time the run had reached), so an algebraic decay is fitted against the time since the launch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

SEGMENTS = 16
DROP = 0.1  # ln r: a fall (rise) of r by about 10 %
MONOTONE = 0.75  # share of consecutive stretches in which the envelope falls
BAND = 0.01  # ln r: the envelope within 1 %


@dataclass(frozen=True)
class Tail:
    """The fits of r's envelope over a trajectory's tail (see the module docstring for the criterion)."""

    trend: str  # "decays", "grows", "band", "irregular"
    kind: str  # "exponential", "algebraic" where it decays, else ""
    rate: float  # the exponential fit's lam (d ln r / dt)
    exponent: float  # the algebraic fit's k (r ~ t^-k)
    residual_exponential: float  # rms of ln r about each fit
    residual_algebraic: float
    r_first: float  # the envelope in the first and the last stretch
    r_last: float
    t_first: float
    t_last: float

    def to_json(self) -> dict:
        return {"trend": self.trend, "kind": self.kind or None, "rate": self.rate, "exponent": self.exponent,
                "residual_exponential": self.residual_exponential, "residual_algebraic": self.residual_algebraic,
                "r_first": self.r_first, "r_last": self.r_last, "t_first": self.t_first, "t_last": self.t_last}


def envelope(t, r, segments: int = SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """(time of the top, largest r) of each of `segments` equal stretches of [t[0], t[-1]] (empty ones left out)."""
    t, r = np.asarray(t, float), np.asarray(r, float)
    edges = np.linspace(t[0], t[-1], segments + 1)
    which = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, segments - 1)
    tc, env = [], []
    for k in range(segments):
        sel = which == k
        if sel.any():
            j = int(np.argmax(r[sel]))  # the top's own time (a stretch's centre biases a steep decay's fit)
            tc.append(float(t[sel][j]))
            env.append(float(r[sel][j]))
    return np.array(tc), np.array(env)


def _fit(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """(slope, rms residual) of the least-squares line y = a + slope x."""
    A = np.vstack([np.ones_like(x), x]).T
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    res = y - A @ coef
    return float(coef[1]), float(math.sqrt(np.mean(res**2)))


def tail(t, r, segments: int = SEGMENTS) -> Tail:
    """The trend of r's envelope over t (times from the launch, t[0] > 0) and its fits."""
    t = np.asarray(t, float)
    if t[0] <= 0:
        raise ValueError("the tail's times must be measured from the launch (t > 0)")
    tc, env = envelope(t, r, segments)
    if len(env) < 4 or not np.all(np.isfinite(env)):
        return Tail("irregular", "", math.nan, math.nan, math.nan, math.nan, math.nan, math.nan, t[0], t[-1])
    lnr = np.log(np.maximum(env, 1e-300))
    lam, e_exp = _fit(tc, lnr)
    slope, e_alg = _fit(np.log(tc), lnr)
    change = lnr[-1] - lnr[0]
    falls = float(np.mean(np.diff(lnr) < 0))
    if change < -DROP and falls >= MONOTONE:
        trend = "decays"
        kind = "algebraic" if e_alg < 0.5 * e_exp else "exponential"
    elif change > DROP:
        trend, kind = "grows", ""
    elif np.ptp(lnr) < BAND:
        trend, kind = "band", ""
    else:
        trend, kind = "irregular", ""
    return Tail(trend, kind, lam, -slope, e_exp, e_alg, float(env[0]), float(env[-1]), float(t[0]), float(t[-1]))


def windings(angles) -> np.ndarray:
    """Whole turns each row of `angles` (a ball angle over the tail, sampled finely enough that it moves
    less than pi between samples) makes from its first to its last value, signed."""
    a = np.unwrap(np.atleast_2d(np.asarray(angles, float)), axis=1)
    return np.trunc((a[:, -1] - a[:, 0]) / (2 * math.pi)).astype(int)
