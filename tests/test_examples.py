"""The examples run as a user runs them: the quick start prints a certified mesh, the STEP
example an exact section meshed and certified (when OCP, the [step] extra, is installed)."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from pds_plugin.analysis.quality import ASPECT_BOUND, ASPECT_EQUILATERAL

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_quickstart_prints_an_ok_certificate_and_the_quality_statistics():
    result = subprocess.run([sys.executable, str(EXAMPLES / "quickstart.py")],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("certificate: ok")
    stats = dict(re.findall(r"^  (\w+) +(\S+)$", result.stdout, flags=re.MULTILINE))
    assert ASPECT_EQUILATERAL <= float(stats["aspect_min"])
    assert float(stats["aspect_max"]) <= ASPECT_BOUND            # Theorem 1
    assert 30 <= float(stats["angle_min"]) and float(stats["angle_max"]) <= 120


def test_torsion_constants_agree_with_the_closed_forms_to_the_order_of_the_elements():
    """J = 2∫φ is an energy of the stress function: its error falls as h^(2p), so about
    alpha² for P1 and alpha⁴ for P2 on the drawing's true circle (issue 23)."""
    import pytest
    pytest.importorskip("skfem")
    result = subprocess.run([sys.executable, str(EXAMPLES / "torsion.py")],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    rates = re.findall(r"^(circle r=1|rectangle 2x1) +exact J = \S+; rate of the error in "
                       r"alpha: P1 (\S+), P2 (\S+)$", result.stdout, flags=re.MULTILINE)
    assert [name for name, _, _ in rates] == ["circle r=1", "rectangle 2x1"]
    for _, p1, p2 in rates:
        assert float(p1) >= 1.8 and float(p2) >= 3.2
    finest = re.findall(r"^(?:circle r=1|rectangle 2x1) +0\.05 .* (\S+) +\S+ +(\S+)$",
                        result.stdout, flags=re.MULTILINE)
    assert len(finest) == 2
    for p1_error, p2_error in finest:
        assert float(p1_error) < 1e-2 and float(p2_error) < 1e-4


def test_section_step_prints_an_ok_certificate_in_the_cutting_plane(tmp_path):
    pytest.importorskip("OCP", reason="OCP (the [step] extra) is not installed")
    result = subprocess.run([sys.executable, str(EXAMPLES / "section_step.py"), str(tmp_path)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "graded certificate: ok" in result.stdout
    assert "3D vertices in the plane z = " in result.stdout and ": True" in result.stdout
    assert (tmp_path / "section_step.ply").stat().st_size > 0
