"""docs/reference/config.md is what tools/gen_config_reference.py writes from today's code."""
import runpy
from pathlib import Path

TOOL_PATH = Path(__file__).resolve().parents[2] / "tools" / "gen_config_reference.py"
TOOL = runpy.run_path(str(TOOL_PATH))


def test_config_reference_is_current():
    assert TOOL["OUTPUT"].read_text() == TOOL["render"](), (
        "docs/reference/config.md is stale: run python tools/gen_config_reference.py")


def test_reference_lists_a_known_setting_with_its_range():
    text = TOOL["render"]()
    assert "## StopConfig" in text
    assert "| `interval_s` | `float` | `600.0` | (0.0, inf) |" in text
