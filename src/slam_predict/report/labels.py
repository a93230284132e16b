"""Human labels of the four error components, shared by the report's model sections."""
from __future__ import annotations

LABELS = {"trans_mean": "mean translational error", "trans_std": "std of translational error",
          "rot_mean": "mean rotational error", "rot_std": "std of rotational error"}
