"""examples/analysis/analyse.py on a run of examples/analysis/gas.toml: the trajectory
read with gsd, g(r) and the MSD (from the image flags) with freud, the speeds against
Maxwell's, a PNG. Skipped, saying so, where gsd, freud or matplotlib are missing."""

import json
import os
import subprocess
import sys

import pytest

for module in ("gsd.hoomd", "freud", "matplotlib"):
    pytest.importorskip(module, reason=f"{module} not installed (pip install gsd freud-analysis matplotlib)")

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "examples", "analysis", "analyse.py")


def test_the_analysis_example_finds_a_gas_in_equilibrium(tmp_path):
    out = subprocess.run([sys.executable, SCRIPT, "--png", "a.png"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    f = json.loads(out.stdout)
    assert f["frames"] == 51 and (tmp_path / "a.png").stat().st_size > 10_000
    # No pair closer than contact; uncorrelated far apart.
    assert f["g_inside_contact_max"] == 0.0 and abs(f["g_far_mean"] - 1.0) < 0.03
    # Ballistic at first (before the mean free time), then diffusive at Enskog's rate
    # (within the 1000 spheres' noise and the known excess of low-density diffusion).
    assert 0.8 < f["ballistic_ratio_first_lag"] < 1.05
    assert 0.9 < f["diffusion"] / f["diffusion_enskog"] < 1.3
    # Maxwell's speeds (an elastic gas): the histogram within its noise of the curve.
    assert f["speed_hist_vs_maxwell_max_abs"] < 0.12 * f["maxwell_peak"]
