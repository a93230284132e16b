"""tools/run_campaign.sh refuses a bad ``--part`` with one line and exit code 2, before any work."""
import subprocess
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "tools" / "run_campaign.sh"


@pytest.mark.parametrize("args, message", [
    (["fidelity_seed_study_2", "--part", "half"], "--part must be fit or judge, got 'half'"),
    (["robots", "--part", "fit"], "--part only applies to the campaigns with parts.yaml"),
])
def test_bad_part_is_one_line_and_exit_2(args, message):
    proc = subprocess.run(["bash", str(SCRIPT), *args], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.strip().splitlines() == [f"run_campaign: {message}"]
