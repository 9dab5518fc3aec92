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


def test_section_step_prints_an_ok_certificate_in_the_cutting_plane(tmp_path):
    pytest.importorskip("OCP", reason="OCP (the [step] extra) is not installed")
    result = subprocess.run([sys.executable, str(EXAMPLES / "section_step.py"), str(tmp_path)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "graded certificate: ok" in result.stdout
    assert "3D vertices in the plane z = " in result.stdout and ": True" in result.stdout
    assert (tmp_path / "section_step.ply").stat().st_size > 0
