"""Charts that certify a resolution (issue 34 item 3), on a toy follower whose spectrum is planted: a stable
window narrower than the grid is found by the certified row (and missed with refinement off, the negative
control); a grid point where the solve fails is "not computed" with why, one where the closed form has no
solution "does not exist", and neither is drawn as stable or unstable."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis.loading import AnalysisError
from adbgen.analysis.orbits import charts

C1, C2 = 1.723, 1.733  # the planted window (B's wedge at eps = 1e-5 in the paper's Fig. 11, as measured)


class Toy:
    """A 'steady state' that is its parameters; its spectrum a pair whose real part is the planted margin.
    Newton 'fails' inside FAIL (a band of lambda_1)."""

    def __init__(self, fail=()):
        self.last = np.zeros(2)
        self.fail = fail

    @staticmethod
    def margin(l1):
        return min(max(3.0 * (C1 - l1), 5.0 * (l1 - C2)), 0.4 * (4.0 - l1))

    def solve(self, p, guess=None):
        l1 = float(p[0])
        if self.fail and self.fail[0] <= l1 <= self.fail[1]:
            raise AnalysisError("Newton failed (planted)")
        m = self.margin(l1)
        return np.array(p, float), np.array([m + 2j, m - 2j, -1.0])

    def accept(self, state):
        self.last = np.array(state, float)


def pmap(lam):
    return np.array(lam, float)


LAM1 = np.linspace(0.5, 5.0, 81)


def _line(refine: bool):
    f = Toy()
    spectra, states = charts._row(f, pmap, LAM1, 1e-5, 40, np.array([LAM1[40], 1e-5]))
    cert = charts.Certify((LAM1[1] - LAM1[0]) / 8, 0.02, True, refine)
    return cert.line(f, pmap, LAM1, lambda x: (x, 1e-5), (spectra, states), False, cert.res1)


def test_row_finds_the_planted_window():
    line = _line(True)
    narrow = [w for w in line.windows if w[1] < 3]
    assert narrow == [pytest.approx((C1, C2), abs=1e-9)]
    assert all(c.bracket is None for c in line.changes)


def test_row_without_refinement_misses_it():
    line = _line(False)
    assert not [w for w in line.windows if w[1] < 3]


def test_failed_cells_are_not_computed_with_why():
    f = Toy(fail=(1.01, 1.12))  # the columns 1.0625 and 1.11875
    reasons = {}
    spectra, _ = charts._row(f, pmap, LAM1, 1e-5, 40, np.array([LAM1[40], 1e-5]), None, reasons)
    failed = [j for j in range(len(LAM1)) if 1.01 <= LAM1[j] <= 1.12]
    assert len(failed) == 2 and all(spectra[j] is None for j in failed)
    assert set(reasons) == set(failed)
    assert all(why.startswith("not computed") and "Newton failed" in why for why in reasons.values())
    assert spectra[0] is not None  # the march goes on past them
    # three failures in a row end the march: the rest of the row is "not computed" too, never "does not exist"
    reasons = {}
    spectra, _ = charts._row(Toy(fail=(1.0, 1.2)), pmap, LAM1, 1e-5, 40, np.array([LAM1[40], 1e-5]), None, reasons)
    assert spectra[0] is None and reasons[0].startswith("not computed")


class Retried(Toy):
    def solve(self, p, guess=None):
        if guess is not None:  # from the closed form, Newton converges
            return np.array(p, float), np.array([-1.0 + 2j, -1.0 - 2j])
        return super().solve(p)


def test_closed_form_retry_and_does_not_exist():
    reasons = {}

    def retry(p):  # the closed form: no solution below 1.1 ("does not exist"), a start for Newton above
        return None if p[0] < 1.1 else np.array(p, float)
    spectra, _ = charts._row(Retried(fail=(1.01, 1.12)), pmap, LAM1, 1e-5, 40, np.array([LAM1[40], 1e-5]), retry,
                             reasons)
    j_none, j_retried = [j for j in range(len(LAM1)) if 1.01 <= LAM1[j] <= 1.12]
    assert reasons == {j_none: reasons[j_none]} and reasons[j_none].startswith("does not exist")
    assert spectra[j_retried] is not None and spectra[j_none] is None
    # negative control: without the closed form, both are "not computed"
    reasons = {}
    charts._row(Retried(fail=(1.01, 1.12)), pmap, LAM1, 1e-5, 40, np.array([LAM1[40], 1e-5]), None, reasons)
    assert sorted(reasons) == [j_none, j_retried] and all(w.startswith("not computed") for w in reasons.values())


def test_missing_cells_drawn_apart(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    class C:
        lam1, lam2 = LAM1[:3], np.array([1e-5, 1e-4])
        stable = np.array([[1, -1, -2], [0, 1, 1]])
    fig, ax = plt.subplots()
    charts._draw_missing(ax, C, 1.0)
    labels = sorted(line.get_label() for line in ax.lines)
    assert labels == ["does not exist", "not computed (failed)"]
    plt.close(fig)


class Line:
    """A toy curve for the continuer: u = lambda, no test function; its stability margin the planted one."""

    size = 2
    test_names = ()
    weights = None

    def parameter(self, x):
        return float(x[1])

    def evaluate(self, x):
        return np.array([x[0] - x[1]]), np.array([[1.0, -1.0]])

    def data(self, x):
        return float(x[1])

    def tests(self, x, data):
        return np.zeros(0)

    def special(self, name, x, data):
        return None

    def accept(self, x, data):
        pass


class Watched(Line):
    def margins(self, lam):
        return np.array([Toy.margin(lam)])


def test_continuer_does_not_step_over_a_watched_window():
    """`continue --orbits` at eps = 1e-5 stepped from 1.7448 to 1.6948 over B's wedge: with the stability
    margin watched, the steps shrink near it and land inside; without (negative control) they step over."""
    from adbgen.analysis.orbits import continuer

    def inside(curve):
        s = continuer.Settings(ds=0.05, ds_max=0.05, max_points=400, bounds=(1.5, 2.0 + 1e-9), fold_test=False)
        br = continuer.run(curve, np.array([2.0, 2.0]), -1.0, s)
        return [pt.x[1] for pt in br.points if C1 < pt.x[1] < C2]
    assert inside(Watched())
    assert not inside(Line())


def test_json_says_what_is_certified():
    from types import SimpleNamespace

    line = _line(True)
    stable = np.zeros((2, len(LAM1)), dtype=int)
    stable[0, 3] = -1
    for refine in (True, False):
        ch = charts.Chart(SimpleNamespace(name="toy"), ("Omega", "epsilon"), True, LAM1, np.array([1e-5, 1e-4]), stable, [],
                          [], [], lines={"rows": {0: line}, "columns": {}, "reasons": {(0, 3): "not computed: planted"}},
                          certify=charts.Certify(0.007, 0.02, True, refine))
        j = ch.to_json(False)
        cert = j["resolution"]["certified"]
        assert cert["refined"] is refine and (cert["Omega"] == 0.007) is refine
        assert "holds a sample" in cert["statement"] if refine else "not certified" in cert["statement"]
    assert [w for w in j["windows"]["rows"][0]["stable"] if w[1] < 3] == [pytest.approx([C1, C2], abs=1e-9)]
    assert j["not_computed"] == [{"row": 0, "column": 3, "Omega": LAM1[3], "epsilon": 1e-5, "why": "not computed: planted"}]
    assert j["resolution"]["Omega"] == pytest.approx(LAM1[1] - LAM1[0])  # the grid's spacing, kept
