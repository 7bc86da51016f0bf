"""Units of a generated model and values typed with units on the command line (issue 24 item 1).

    units(model)                     Units: time, each state's and parameter's unit, the scales
    quantity(text, unit, what)       "300rad/s", "3000rpm", "0.5mm", "90deg", "3*pi/4" -> a float in `unit`
    duration(text, model, p)         "20s", "640rev" (revolutions of the spin), "1000" -> t in the model's time
    default_t_end(model, p)          the thesis' t = 1000 at Omega = 4 as revolutions: 4000 / speed
    default_threshold(model, p)      t_dec's threshold: a tenth of the eccentricity (thesis: 1e-3 = delta / 10)
    show(value, unit)                "10.4 mm", "5.46 s", "0.001" (dimensionless): a number for a table

What a model says about itself (TIME_UNIT, STATE_UNITS, SCALES, PARAM_DOMAINS of the generated
module, issue 19; `Model`'s properties) decides every default here; nothing depends on a family's or
a model's name.  Plain numbers and
expressions in pi are read without a units library; anything with a unit goes through pint
(imported on first use only: it costs about half a second, the command line's start-up matters).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import lru_cache

from .loading import AnalysisError, parse_value

DIMENSIONLESS = ("1", "dimensionless", "")
# t_end's default, as the thesis runs its transients: t = 1000 at Omega = 4 (dimensionless time), i.e.
# 2000/pi = 636.6 revolutions of the spin, whatever the model's time unit (10 s at 400 rad/s)
DEFAULT_REVOLUTIONS = 2000.0 / math.pi
# t_dec's default threshold: the eccentricity over this (the thesis' 1e-3 with delta = 0.01; a division,
# so that 0.01 / 10 is the double 1e-3 exactly, which 0.1 * 0.01 is not)
ECCENTRICITY_PER_THRESHOLD = 10


@dataclass(frozen=True)
class Units:
    time: str  # "s" or "1" (dimensionless time)
    states: dict  # state name -> unit
    params: dict  # parameter name -> unit
    scales: dict  # {"eccentricity": parameter, "speed": parameter} where the model has them
    length: str  # the unit of the rotor amplitude r (its AMPLITUDE states')


def _unit(text: str) -> str:
    return "1" if text in DIMENSIONLESS else text


def units(model) -> Units:
    """The model's units as its generated module declares them (`Model.time_unit`, `state_units`,
    `scales`, and PARAM_UNITS)."""
    params = {k: _unit(v) for k, v in zip(model.param_names, model.module.PARAM_UNITS)}
    states = {k: _unit(v) for k, v in zip(model.state_names, model.state_units)}
    return Units(_unit(model.time_unit), states, params, model.scales, states[model.amplitude[0]])


# --- reading values with units ---------------------------------------------------------------------

@lru_cache(maxsize=1)
def _registry():
    import pint

    ureg = pint.UnitRegistry()
    ureg.define("rev = revolution")
    return ureg


_LETTERS = re.compile(r"[A-Za-z_%\u00b0\u00b5]")


def _has_unit(text: str) -> bool:
    """Whether `text` names a unit (anything but numbers, pi, nan and inf, which `parse_value` reads or
    refuses with its own message)."""
    return bool(_LETTERS.search(re.sub(r"\b(pi|nan|inf|infinity)\b|\d[eE][+-]?\d", "", text, flags=re.I)))


def _parse(text: str, what: str):
    """A pint Quantity from `text` (one line on failure)."""
    if len(text) > 200:
        raise AnalysisError(f"{what}: {text[:40]!r}...: too long")
    ureg = _registry()
    try:
        q = ureg.Quantity(text)
    except Exception as exc:  # pint raises many kinds for bad input; all mean the same to a user
        reason = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise AnalysisError(f"{what}: cannot read {text!r} ({reason})") from None
    if not isinstance(q, ureg.Quantity) or not isinstance(q.magnitude, (int, float)) or not math.isfinite(q.magnitude):
        raise AnalysisError(f"{what}: {text!r} is not a finite number with a unit")
    return q


def check_syntax(text: str, what: str) -> str:
    """`text` if it is a number, an expression in pi or a quantity with a unit pint knows."""
    text = str(text).strip()
    if _has_unit(text):
        _parse(text, what)
    else:
        parse_value(text, what)
    return text


def quantity(text: str, unit: str, what: str) -> float:
    """`text` in `unit`: a plain number (already in `unit`), an expression in pi, or a value with a
    unit of the same dimension ("300rad/s", "3000rpm" for rad/s; "0.5mm" for m; "90deg" for rad)."""
    text = str(text).strip()
    if not _has_unit(text):
        return parse_value(text, what)
    q = _parse(text, what)
    target = "dimensionless" if unit in DIMENSIONLESS else unit
    try:
        value = float(q.to(target).magnitude)
    except Exception:
        shown = "a pure number" if unit in DIMENSIONLESS else unit
        raise AnalysisError(f"{what}: {text!r} is not in {shown}"
                            + (" (this model's parameter is dimensionless: give a number)" if unit in DIMENSIONLESS else "")) from None
    if not math.isfinite(value):
        raise AnalysisError(f"{what}: {text!r} is not finite")
    return value


def duration(text: str, model, p, what: str = "--t-end") -> float:
    """A time span in the model's time unit: a number (in it), a time with a unit (models in
    seconds), or a number of revolutions of the spin ("640rev", "100 turn": 2 pi N / speed)."""
    text = str(text).strip()
    u = units(model)
    if not _has_unit(text):
        return parse_value(text, what)
    q = _parse(text, what)
    if q.dimensionless and not q.unitless:  # an angle: revolutions of the spin
        speed = u.scales.get("speed")
        if speed is None:
            raise AnalysisError(f"{what}: {model.name} has no spin speed parameter to count revolutions with; "
                                f"give a time")
        omega = float(p[model.param_names.index(speed)])
        if not omega > 0:
            raise AnalysisError(f"{what}: revolutions need a positive {speed}, got {omega:g}")
        return float(q.to("radian").magnitude) / omega
    if u.time == "1":
        raise AnalysisError(f"{what}: {model.name} runs in dimensionless time; give a number or revolutions "
                            f"(e.g. 640rev), not {text!r}")
    return quantity(text, u.time, what)


# --- defaults that scale with the model ------------------------------------------------------------

def default_t_end(model, p) -> tuple[float, str]:
    """(t_end, why): DEFAULT_REVOLUTIONS of the spin at the model's speed (the thesis' t = 1000 at
    Omega = 4; 10 s at 400 rad/s), or 1000 time units where the model has no speed scale."""
    speed = units(model).scales.get("speed")
    if speed is not None:
        omega = float(p[model.param_names.index(speed)])
        if omega > 0:
            return 4000.0 / omega, (f"{DEFAULT_REVOLUTIONS:.1f} revolutions at {speed} = "
                                    f"{show(omega, units(model).params[speed], 6)}")
    return 1000.0, "no speed scale: 1000 time units"


def default_threshold(model, p) -> tuple[float, str]:
    """(threshold, why): a tenth of the eccentricity (the thesis' 1e-3 at delta = 0.01; 0.05 mm for an
    eccentricity of 0.5 mm), or 1e-3 where the model has no eccentricity scale."""
    ecc = units(model).scales.get("eccentricity")
    if ecc is not None:
        eps = float(p[model.param_names.index(ecc)])
        if eps > 0:
            return eps / ECCENTRICITY_PER_THRESHOLD, f"a tenth of {ecc} = {show(eps, units(model).params[ecc], 6)}"
    return 1e-3, "no eccentricity scale: 1e-3"


# --- writing values with units ---------------------------------------------------------------------

_PREFIXES = ((1e3, "k"), (1.0, ""), (1e-3, "m"), (1e-6, "\u00b5"), (1e-9, "n"))
_PREFIXABLE = {"m", "s", "N"}


def show(value: float | None, unit: str, digits: int = 4) -> str:
    """A value for a table: a plain number in dimensionless units, else with its unit; a simple unit
    (m, s, N) in engineering form (0.0104 m -> "10.4 mm", 5.46e-05 m -> "54.6 \u00b5m")."""
    if value is None or not math.isfinite(value):
        return "-"
    if unit in DIMENSIONLESS:
        return f"{value:.{digits}g}"
    if unit in _PREFIXABLE and value != 0:
        factor, prefix = next(((f, pre) for f, pre in _PREFIXES if abs(value) >= f * (1 - 5e-4)), _PREFIXES[-1])
        return f"{value / factor:.{digits}g} {prefix}{unit}"
    return f"{value:.{digits}g} {unit}"


def axis_label(symbol: str, unit: str) -> str:
    """'$r$ (m)' or '$r$' for a dimensionless quantity."""
    return symbol if unit in DIMENSIONLESS else f"{symbol} ({unit})"


# --- NAME=VALUE assignments with units, parameters within their domains ------------------------------

def assignments(items, what: str, unit_of: dict) -> dict[str, float]:
    """``["NAME=VALUE", ...]`` (--set, --y0) -> {name: value in the model's unit of NAME}; unknown
    names, a name given twice and unreadable values are one line each."""
    out: dict[str, float] = {}
    kind = "parameter" if what == "--set" else "state"
    for item in items or ():
        name, sep, value = str(item).partition("=")
        name = name.strip()
        if not sep or not name:
            raise AnalysisError(f"{what}: expected NAME=VALUE, got {item!r}")
        if name not in unit_of:
            raise AnalysisError(f"{what}: {name!r} is not a {kind}; {kind}s: {', '.join(unit_of)}")
        if name in out:
            raise AnalysisError(f"{what}: {name} given twice")
        out[name] = quantity(value, unit_of[name], f"{what} {name}")
    return out


DOMAINS = {"positive": (lambda v: v > 0, "must be positive"), "nonnegative": (lambda v: v >= 0, "must be non-negative"),
           "real": (lambda v: True, "")}


def domains(model) -> dict:
    """{parameter: "positive" | "nonnegative" | "real"} as the generated module declares them
    (`Model.param_domains`: the assumptions of the derivation's symbols)."""
    return dict(zip(model.param_names, model.param_domains))


def params(model, values: dict) -> "np.ndarray":
    """The parameter vector: DEFAULTS with `values` (from --set), each checked against its domain as
    a scene value is (a negative mass is refused, not run)."""
    dom = domains(model)
    unit = units(model).params
    for name, value in values.items():
        test, why = DOMAINS.get(dom.get(name, "real"), DOMAINS["real"])
        if not test(value):
            shown = show(value, unit.get(name, "1"), 6)
            raise AnalysisError(f"--set {name}: {why}, got {shown}")
    return model.params(values)
