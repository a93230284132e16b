"""Figures like the thesis' Figure 7.2: regression lines over all buildings (matplotlib Agg)."""
from __future__ import annotations

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from slam_predict.atomic import atomic_path  # noqa: E402
from slam_predict.learn.dataset import COMPONENTS, UNITS, Dataset  # noqa: E402
from slam_predict.learn.evaluate import scores  # noqa: E402
from slam_predict.learn.tables import SYMBOLS  # noqa: E402


def regression_figure(data: Dataset, features: dict[str, str], path: os.PathLike | str,
                      title: str = "") -> None:
    """2×2 panels, one per component: buildings (black dots) and the OLS line on ``features[c]``.

    ``features`` maps component → feature name (or ``ref_*`` reference column).
    """
    fig, axes = plt.subplots(2, 2, figsize=(10, 8))
    for ax, component in zip(axes.ravel(), COMPONENTS, strict=False):
        name = features.get(component)
        if name is None:
            ax.set_visible(False)
            continue
        x = data.reference[name] if name in data.reference else \
            data.X[:, data.feature_names.index(name)]
        y = data.target(component)
        slope, intercept = np.polyfit(x, y, 1)
        grid = np.linspace(np.nanmin(x), np.nanmax(x), 50)
        r2 = scores(y, slope * x + intercept)["r2"]
        ax.plot(x, y, "k.", label="buildings")
        ax.plot(grid, slope * grid + intercept, "-", color="tab:blue",
                label=f"y = {slope:.3g}·x + {intercept:.3g}")
        ax.set_xlabel(name)
        ax.set_ylabel(f"{SYMBOLS[component]} [{UNITS[component]}]")
        ax.set_title(f"{SYMBOLS[component]}: R² = {r2:.3f} (all {len(y)} buildings)", fontsize=10)
        ax.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    with atomic_path(path, suffix=".png") as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
