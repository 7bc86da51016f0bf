"""`adbgen reproduce` gives the same document on any x86-64 machine (issue 23).

The parts that change from one machine to another are the loose-tolerance and chaotic computations: one
last-bit difference of an elementary function grows into a different t_dec.  Here the transient rows most
sensitive to it (Fig. 5.8(b), (d): their t_dec at rtol 1e-6 moved by whole oscillations between two
machines before the pin) are computed in child processes: twice with the pinned environment of
`adbgen reproduce`, and once on an emulated second machine (glibc's AVX variants masked as well, as on a
processor without AVX); the document lines and every raw number are byte-identical.  Negative control:
without the pinned environment (glibc's FMA variants on this processor) the raw numbers differ, so the
emulation does change what an unpinned run computes.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from adbgen.analysis.engines.compiled import libm
from adbgen.analysis.reproduction import PINNED_HWCAPS, environment_pinned, pinned_environment
from toolchain import require_tool

ROOT = Path(__file__).resolve().parents[4]
SCRIPT = """
from adbgen.families.single_plane.science import reproduce as r
rows = [r.transient(t) for t in r.TRANSIENTS if t.figure in ("5.8(b)", "5.8(d)")]
print("\\n".join(r._transient_section(rows)))
for t in rows:
    print([repr(s.t_dec) for s in t["sims"].values()], repr(t["ode45"].t_dec))
"""


def _run(env: dict) -> str:
    env = {**env, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return proc.stdout


def _cpu_has(flag: str) -> bool:
    return any(flag in line.split() for line in Path("/proc/cpuinfo").read_text().splitlines()
               if line.startswith("flags"))


def test_the_environment_pin_is_added_and_kept():
    env = pinned_environment({"GLIBC_TUNABLES": "glibc.malloc.check=0:glibc.cpu.hwcaps=-AVX"})
    assert environment_pinned(env) and not environment_pinned({"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX"})
    assert env["GLIBC_TUNABLES"] == "glibc.malloc.check=0:glibc.cpu.hwcaps=-AVX," + ",".join(PINNED_HWCAPS)


def test_sensitive_rows_are_byte_identical_on_an_emulated_second_machine():
    require_tool(libm() == "sleef-cinz", "SLEEF (libsleef-dev, the compiled engines' pinned libm)")
    base = {k: v for k, v in os.environ.items() if k != "GLIBC_TUNABLES"}
    pinned = pinned_environment(base)
    first, again = _run(pinned), _run(pinned)
    older = dict(pinned, GLIBC_TUNABLES=pinned["GLIBC_TUNABLES"] + ",-AVX")  # a processor without AVX
    assert first == again == _run(older)
    assert "5.8(b)" in first and "567.48" in first
    if _cpu_has("fma") and _cpu_has("avx2"):  # the negative control needs a processor with the FMA variants
        assert _run(base) != first
