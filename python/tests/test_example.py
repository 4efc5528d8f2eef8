"""examples/python/tutorial.py runs and draws its figure."""
import os
import re
import subprocess
import sys

from conftest import ROOT


def test_the_tutorial_example_runs(tmp_path):
    png = tmp_path / "residual.png"
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "python" / "tutorial.py"), str(png)],
                          capture_output=True, text=True, env={**os.environ, "MPLBACKEND": "Agg"}, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert "Missing: thermal_drift" in proc.stdout  # the effect the truth scene holds and the model lacks
    before, after = map(float, re.search(r"residual RMS ([\d.]+) µm → ([\d.]+) µm", proc.stdout).groups())
    # With the effect the residual is the demo's probe noise, σ 0.5 µm: over 252 points the RMS of pure noise lies
    # within 0.5 ± 3 × 0.5/√(2·252) = 0.5 ± 0.067 µm; without it, the missing drift's micrometres remain.
    assert after < 0.567 and before > 2 * after
    # A PNG, and a real figure (two panels of coloured points), not an empty canvas.
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
