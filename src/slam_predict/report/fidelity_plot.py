"""The fidelity plot: ours / the seed study's, per building, against the building's free area."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import NullFormatter, ScalarFormatter  # noqa: E402

from slam_predict.collect.fidelity import Comparison  # noqa: E402
from slam_predict.report.figures import png_bytes  # noqa: E402

AREA_TICKS = (50, 100, 200, 300, 500, 1000, 2000, 3000, 5000, 10000, 20000, 50000)  # m²
SERIES = (("trans_mean", "ε_t", "o"), ("rot_mean", "ε_r", "s"),
          ("path_length_mean", "path length", "^"))


def ratio_vs_area_png(comparisons: list[Comparison]) -> bytes:
    """PNG: one panel per campaign, the three ratios ours/theirs against free area (m², log x),
    with the ε_t acceptance band [0.85, 1.2] shaded and the ratio 1 drawn."""
    count = max(len(comparisons), 1)
    fig, axes = plt.subplots(1, count, figsize=(6.0 * count, 4.2), squeeze=False)
    for ax, comparison in zip(axes[0], comparisons, strict=False):
        areas = np.array([row["free_area_m2"] for row in comparison.rows], dtype=float)
        ax.axhspan(0.85, 1.2, color="0.9", label="ε_t / path band [0.85, 1.2]")
        ax.axhline(1.0, color="0.4", linewidth=0.8)
        for key, label, marker in SERIES:
            ax.scatter(areas, comparison.ratios(key), marker=marker, label=label)
        ax.set_xscale("log")
        ax.xaxis.set_major_formatter(ScalarFormatter())   # 1000, not 10^3
        ax.xaxis.set_minor_formatter(NullFormatter())     # no overlapping 3x10^2, 4x10^2...
        ax.set_xticks(_area_ticks(areas))
        ax.set_xlabel("free area (m²)")
        ax.set_ylabel("ours / seed study")
        ax.set_title(f"{comparison.name}: size trend ρ = {comparison.size_trend():.2f}")
        ax.legend(fontsize=8)
    fig.tight_layout()
    return png_bytes(fig)


def _area_ticks(areas: np.ndarray) -> list[int]:
    """The round areas (m²) within 15 % of the plotted range (ticks widen the axis at most that)."""
    finite = areas[np.isfinite(areas)]
    if finite.size == 0:
        return []
    low, high = finite.min() / 1.15, finite.max() * 1.15
    return [tick for tick in AREA_TICKS if low <= tick <= high]
