"""The quick-start example runs as a user runs it and prints a certified mesh."""

import re
import subprocess
import sys
from pathlib import Path

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
