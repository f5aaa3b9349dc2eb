"""The outcome of a fit: parameters, meshes, volume, length, condition, mass, history."""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.fit.config import FitConfig

RESULT_SCHEMA_VERSION = 2
STATUS_COMPLETE = "complete"
# ran to the end, but its figures cannot be trusted (core.fit.reliability: the reasons)
STATUS_UNRELIABLE = "unreliable"
STATUS_CANCELLED = "cancelled"    # stopped by the caller: the best state reached is kept
STATUS_DIVERGED = "diverged"      # the loss turned non-finite: the best state before is kept
STATUSES = (STATUS_COMPLETE, STATUS_UNRELIABLE, STATUS_CANCELLED, STATUS_DIVERGED)
FINISHED = (STATUS_COMPLETE, STATUS_UNRELIABLE)   # the fit ran all its steps


@dataclass(frozen=True, eq=False)
class FitResult:
    """A fitted animal over T frames (metres, world frame: z up, water at z = 0)."""

    betas: np.ndarray            # (M, 4) part log scales, overall scale included
    pose_aa: np.ndarray          # (T, M, 3) axis-angle per part
    transl: np.ndarray           # (T, 3) root joint positions
    frame_idx: np.ndarray        # (T,) clip frame indices
    time_s: np.ndarray           # (T,)
    iou: np.ndarray              # (T,) hard IoU of render and mask
    rest_verts: np.ndarray       # (V, 3) the fitted shape in the rest pose
    posed_verts: np.ndarray      # (T, V, 3)
    faces: np.ndarray            # (F, 3) int64
    albedo: np.ndarray           # (Ht, Wt) fitted grayscale texture in [0, 1]
    f_water: np.ndarray          # (3,) fitted water filter
    light: dict[str, np.ndarray]  # fitted SG light: axes (K, 3), sharpness (K,), amplitude (K, 3)
    volume_m3: float
    length_m: float
    bci: float
    mass_kg: float
    density_kg_m3: float
    loss_history: tuple[dict, ...]
    timings_s: dict[str, float]
    config: FitConfig
    warnings: tuple[str, ...]
    status: str = STATUS_COMPLETE    # one of STATUSES
    status_message: str = ""         # why a fit ended early or is unreliable, in words
    reasons: tuple[str, ...] = ()    # why its figures cannot be trusted (unreliable)
    profile: np.ndarray | None = None  # (2, K) profile field (None: fitted without one)
    edge_blur_px: float = float("nan")  # blur index of the animal's edge, clip px (NaN: none)

    @property
    def finished(self) -> bool:
        """Whether the fit ran all its steps (complete, or unreliable)."""
        return self.status in FINISHED

    def to_json(self) -> dict:
        """The result file's content (arrays and meshes are written beside it: result_io)."""
        return {
            "schema_version": RESULT_SCHEMA_VERSION,
            "status": self.status,
            "status_message": self.status_message,
            "reasons": list(self.reasons),
            "volume_m3": self.volume_m3,
            "length_m": self.length_m,
            "bci": self.bci,
            "mass_kg": self.mass_kg,
            "density_kg_m3": self.density_kg_m3,
            "mean_iou": float(self.iou.mean()),
            "betas": self.betas.tolist(),
            "profile": None if self.profile is None else self.profile.tolist(),
            "edge_blur_px": (float(self.edge_blur_px) if np.isfinite(self.edge_blur_px)
                             else None),
            "f_water": self.f_water.tolist(),
            "frames": [{"frame": int(f), "time_s": float(t), "iou": float(i),
                        "transl_m": p.tolist(), "pose_aa": q.tolist()}
                       for f, t, i, p, q in zip(self.frame_idx, self.time_s, self.iou,
                                                self.transl, self.pose_aa)],
            "timings": self.timings_s,
            "warnings": list(self.warnings),
            "config": self.config.to_json(),
            "loss_history": list(self.loss_history),
        }
