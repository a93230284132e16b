"""docs/reference/config.md is what tools/gen_config_reference.py writes from today's code."""
import importlib.util
from pathlib import Path

TOOL = Path(__file__).resolve().parents[2] / "tools" / "gen_config_reference.py"


def _tool():
    spec = importlib.util.spec_from_file_location("gen_config_reference", TOOL)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_config_reference_is_current():
    tool = _tool()
    assert tool.OUTPUT.read_text() == tool.render(), (
        "docs/reference/config.md is stale: run python tools/gen_config_reference.py")


def test_reference_lists_a_known_setting_with_its_range():
    text = _tool().render()
    assert "## StopConfig" in text
    assert "| `interval_s` | `float` | `600.0` | (0.0, inf) |" in text
