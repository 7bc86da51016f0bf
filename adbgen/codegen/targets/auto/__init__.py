"""The AUTO-07p target: a user file (func with dfdu and dfdp, stpnt, pvls) and constants files.

Its decisions are made here, from the model's `Continuation` (which the family sets), and handed to
the templates as data (and written as data too, `auto/stages.json`, for the analysis layer:
`stages`): which parameter is continued (PAR index), in which direction and until where,
whether there is a second stage (periodic orbits of an oscillator extension: first in the parameter
the start moved, then in the forcing frequency), whether the start lies on a continuum, which states
give the amplitude printed by pvls.  The templates (templates/auto/) only print; func's bodies are printed by
the C printer in AUTO's dialect (`dialect.AutoDialect`: u, par[APAR(k)], ARRAY2D, doublereal).
"""

from __future__ import annotations

import json

from ....core.oscillator import OSC_COS, OSC_SIN
from .. import Target, columns
from ..c.printer import CPrinter
from .dialect import AutoDialect, par_index as apar

# the output arrays of AUTO-07p's func: f = F(U), dfdu = dF/dU, dfdp = dF/dPAR
_OUT = {"rhs": "f", "jac": "dfdu", "jac_p": "dfdp"}
IPLT = 0
FAMILY_SIGMA = 1.0
RESTART_LABEL = 2  # stage 1 of a forced model ends on this label (UZ; label 1 is the start), stage 2 restarts there


def stages_data(ir, auto: dict) -> dict:
    """What the constants files do, as data (`auto/stages.json`, read by `analysis.auto_orbits.stages`):
    ``first``: stage 1's parameter (0-based model index); ``first_target``: the value its UZSTOP ends
    stage 1 at (a two-stage forced model: the parameter's default), else null; ``second``: stage 2's
    parameter (the forcing frequency), null without a second stage; ``start``, ``start_parameters``:
    stpnt's orbit at t = 0 (the oscillator's states included) and its parameters; ``oscillator``: the
    positions of the extension's oscillator states (paper (40): sin, cos), null for an autonomous
    model; ``continuum``: the start lies on a continuum of balanced states or orbits; ``pinned``: the
    user file regularises that continuum (thesis (3.6), templates/auto/_family.j2); ``uzstop``: c.<model>'s
    bounds on its continued parameter {"parameter", "bounds": [lo, hi], "down": DS < 0}, null where it
    stops at a value instead."""
    two = bool(auto["forced"]) and auto.get("stages") == 2
    k1 = auto["icp"]
    if not auto["forced"]:
        bounds = list(auto["stop"]) if auto["stop"] else None
    elif not two:
        w0 = ir.start_parameters[k1]
        bounds = [w0 * 0.5, w0 * 1.5]  # as templates/auto/_forced.j2's one-stage UZSTOP
    else:
        bounds = None
    return {"first": k1, "first_target": float(ir.parameters[k1].default) if two else None,
            "second": auto["stage2"] if two else None,
            "start": [float(v) for v in ir.start], "start_parameters": [float(v) for v in ir.start_parameters],
            "oscillator": list(auto["osc"]) if auto["forced"] else None, "continuum": bool(auto["continuum"]),
            "pinned": bool(auto["family"]),
            "uzstop": {"parameter": k1, "bounds": [float(b) for b in bounds], "down": bool(auto["down"])} if bounds else None}


class AutoTarget(Target):
    def dialect(self, which, kernel):
        return AutoDialect("u", "par", _OUT[which], columns(kernel), columns_are_parameters=which == "jac_p")

    def skip_reason(self, ir):
        if not ir.autonomous and ir.autonomous_extension is None:
            return ("explicit time and no autonomous extension with a known start orbit "
                    "(AUTO-07p continues autonomous systems only)")
        model = self.model_for(ir)
        if model.start is None or model.continuation is None:
            return "no start point (a steady state or an exact periodic orbit) to continue from"
        return None

    def model_for(self, ir):
        return ir if ir.autonomous else ir.autonomous_extension

    def context(self, ir) -> dict:
        cont = ir.continuation
        names = ir.parameter_names
        k1 = names.index(cont.parameter)
        out = {
            "forced": bool(ir.forcing_frequency),
            "icp": k1,  # 0-based model parameter continued (stage 1)
            "start_value": ir.start_parameters[k1],
            "down": cont.direction < 0,
            "stop": cont.stop,
            "continuum": cont.continuum,
            "note": cont.note.splitlines(),
            "amplitude": tuple(ir.state_names.index(c) for c in ir.core[:2]) if len(ir.core) >= 2 else None,
            "npar_amp": apar(len(ir.parameters)),
            # IPLT: fort.7's principal measure is AUTO's default norm; the amplitude is the last ICP
            "iplt": IPLT,
            # the regularised continuum of balanced states (thesis (3.6), templates/auto/_family.j2):
            # autonomous starts on it only; its zero eigenvalues go to -family_sigma
            "family": bool(cont.continuum) and not ir.forcing_frequency and ir.start_label.startswith("balanced"),
            "family_sigma": FAMILY_SIGMA,
            "restart_label": RESTART_LABEL,
        }
        if ir.forcing_frequency:
            # periodic orbits: either in the parameter the start moved, then (stage 2) in the forcing
            # frequency; or, from an orbit at the defaults, in the forcing frequency at once
            stages = 2 if cont.second else 1
            frequency = cont.second or cont.parameter
            if frequency != ir.forcing_frequency:
                raise ValueError(f"{ir.name}: the continuation in {frequency!r} is not in the forcing frequency "
                                 f"{ir.forcing_frequency!r}")
            out.update(stages=stages, stage2=names.index(ir.forcing_frequency),
                       osc=(ir.state_names.index(OSC_SIN.name), ir.state_names.index(OSC_COS.name)))
        from ...render import source_hash

        out["stages_json"] = json.dumps({"source_hash": source_hash(ir)} | stages_data(ir, out), indent=1)
        return out


TARGET = AutoTarget(
    name="auto",
    files=(("auto/user.c.j2", "{name}/auto/{name}.c"), ("auto/constants.j2", "{name}/auto/c.{name}"),
           # second continuation stage: forced models only (the template renders blank otherwise)
           ("auto/constants_stage2.j2", "{name}/auto/c.{name}.2"),
           # the stages as data (the analysis layer reads this, never the files above)
           ("auto/stages.json.j2", "{name}/auto/stages.json")),
    printer=CPrinter,
    loops=True,
    functions=tuple(_OUT),
    depth=2,
    description="AUTO-07p user file and constants: continuation of steady states or periodic orbits",
)
