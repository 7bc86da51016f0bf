"""The Taylor target: C for the Taylor coefficients of a model's solution (issue 22).

From the same intermediate form as every target, the rhs kernel is decomposed into elementary series
operations (`series`), checked before anything is written against independent references
(`checks`: the Lie derivatives of the printed rhs in 60-digit series arithmetic, and one step against
mpmath's odefun at 30 digits), and printed (`ccode`) as

    <model>/<model>_taylor.h, <model>_taylor.c
        <model>_taylor(t, y, p, order, coef)        the solution's Taylor coefficients to `order`
        <model>_jet(t, tdot, ycoef, p, order, fcoef) f along an input series (directional derivatives)
        and, for a translation unit that #includes the .c (the Taylor engine's driver), the workspace
        struct <model>_ts with _ts_setup, _ts_time, _ts_load and the always-inline _ts_order(w, K, f)

with the loop form over the balls kept (the text does not grow with n).  Its proof (issue 20, `prove`):
the files compiled strictly, both exports compared with the checked series program at the proof's samples.
"""

from __future__ import annotations

from .. import Target
from ...emit import tables
from .ccode import CEmitter
from .series import NotSeries, decompose

MAX_ORDER = 32  # the library functions' largest order (a driver compiles for its own)
TABLE_SIZE = 66  # reciprocals 1/k for k < 66: TS_MAXO up to 64


_memo: dict = {}


def _program(ir):
    """(series program, None) or (None, why not) of a model, made once per intermediate form object."""
    hit = _memo.get(id(ir))
    if hit is None or hit[0] is not ir:
        try:
            hit = (ir, decompose(ir), None)
        except NotSeries as exc:
            hit = (ir, None, str(exc))
        if len(_memo) > 32:
            _memo.clear()
        _memo[id(ir)] = hit
    return hit[1], hit[2]


class TaylorTarget(Target):
    max_order = MAX_ORDER

    def program(self, ir):
        """(series program, None) or (None, why not)."""
        return _program(ir)

    def skip_reason(self, ir):
        prog, why = _program(ir)
        return None if prog is not None else f"no series form ({why})"

    def context(self, ir) -> dict:
        from .checks import check_series

        prog, why = _program(ir)
        check_series(ir, prog)
        em = CEmitter(prog, ir.name)
        body = em.body()
        fields = em.fields()
        return {
            "max_order": MAX_ORDER, "table_size": TABLE_SIZE, "body": body, "fields": fields,
            "setup": em.setup(), "load": em.load(), "time": em.time_node(), "switches": em.switches(),
            "tables": tables(ir.loops.split) if ir.loops is not None else [],
            "n_series": sum(1 for nd in prog.nodes.values() if not nd.ball),
            "n_ball_series": sum(1 for nd in prog.nodes.values() if nd.ball),
            "n_constants": len(em.core_consts) + len(em.ball_consts),
            "n_balls": prog.n_balls, "n_ball_lanes": em.nbp,
        }


# It prints no kernel functions through a dialect (printer None): its C is the series program, printed by
# `ccode` (expressions through the C target's printer), and its templates are templates/taylor/.
TARGET = TaylorTarget(
    name="taylor",
    files=(("taylor/taylor.h.j2", "{name}/{name}_taylor.h"), ("taylor/taylor.c.j2", "{name}/{name}_taylor.c")),
    loops=True,
    description="C: the solution's Taylor coefficients (<model>_taylor) and the rhs's jet (<model>_jet)",
)
