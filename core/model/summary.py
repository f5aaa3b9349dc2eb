"""Figures of a template (or shaped template) and the anatomical targets they must meet.

Targets come from the foundation issue and reference/morphometrics.md §4–§6, as fractions of
body length BL.
"""

from dataclasses import asdict, dataclass

import numpy as np
import torch
import trimesh

from dolphinfit.core.measure.mesh import body_length, mesh_volume, station_profile
from dolphinfit.core.model.template import Template


@dataclass(frozen=True)
class StationFigures:
    """Body width and height at one station."""

    fraction: float
    width_m: float
    height_m: float
    width_bl: float
    hw_ratio: float


@dataclass(frozen=True)
class TemplateSummary:
    """What ``dolphinfit template info`` prints."""

    length_m: float
    volume_m3: float
    volume_per_bl3: float
    watertight: bool
    winding_consistent: bool
    num_verts: int
    num_faces: int
    num_joints: int
    num_groups: int
    max_width_bl: float
    max_width_at: float
    fluke_span_bl: float
    flipper_insertion_bl: float
    dorsal_fin_base_bl: tuple[float, float]
    stations: tuple[StationFigures, ...]

    def to_json(self) -> dict:
        """JSON-ready dict (keys carry units)."""
        return asdict(self)


@dataclass(frozen=True)
class TargetCheck:
    """One anatomical target: the measured value, the accepted range, and the verdict."""

    name: str
    value: float
    low: float
    high: float

    @property
    def ok(self) -> bool:
        """Whether the value lies in [low, high]."""
        return self.low <= self.value <= self.high


def summarize(template: Template) -> TemplateSummary:
    """Measure the template's rest mesh."""
    verts = torch.as_tensor(template.verts, dtype=torch.float64)
    faces = torch.as_tensor(template.faces)
    length = float(body_length(verts, template.rostrum_idx, template.notch_idx))
    volume = float(mesh_volume(verts, faces))
    profile = station_profile(verts, torch.as_tensor(template.station_rings))
    widths, heights = profile.width.numpy(), profile.height.numpy()
    mesh = trimesh.Trimesh(template.verts, template.faces, process=False)

    def fraction_along(idx: np.ndarray) -> np.ndarray:
        return (template.verts[template.rostrum_idx, 0] - template.verts[idx, 0]) / length

    flukes = np.concatenate([template.fin_vertices["fluke_l"], template.fin_vertices["fluke_r"]])
    dorsal_base = fraction_along(template.fin_bases["dorsal_fin"])
    stations = tuple(
        StationFigures(float(f), float(w), float(h), float(w / length), float(h / w))
        for f, w, h in zip(template.station_fractions, widths, heights))
    widest = int(np.argmax(widths))
    return TemplateSummary(
        length_m=length,
        volume_m3=volume,
        volume_per_bl3=volume / length**3,
        watertight=bool(mesh.is_watertight),
        winding_consistent=bool(mesh.is_winding_consistent),
        num_verts=len(template.verts),
        num_faces=len(template.faces),
        num_joints=len(template.joint_names),
        num_groups=len(template.group_names),
        max_width_bl=float(widths[widest] / length),
        max_width_at=float(template.station_fractions[widest]),
        fluke_span_bl=float(np.ptp(template.verts[flukes, 1]) / length),
        flipper_insertion_bl=float(fraction_along(template.fin_bases["flipper_l"]).min()),
        dorsal_fin_base_bl=(float(dorsal_base.min()), float(dorsal_base.max())),
        stations=stations,
    )


def shape_targets(summary: TemplateSummary) -> list[TargetCheck]:
    """The anatomical targets of the template, each with its measured value."""
    hw = {round(s.fraction, 2): s.hw_ratio for s in summary.stations}
    return [
        TargetCheck("volume / BL³", summary.volume_per_bl3, 0.011, 0.015),
        TargetCheck("max width / BL", summary.max_width_bl, 0.17, 0.21),
        TargetCheck("max width position / BL", summary.max_width_at, 0.30, 0.45),
        TargetCheck("HW ratio on the head, 5–15 % (max |HW − 1|)",
                    max(abs(hw[f] - 1.0) for f in (0.05, 0.10, 0.15)), 0.0, 0.1),
        TargetCheck("HW ratio on the tail stock, 75–85 % (max)",
                    max(hw[f] for f in (0.75, 0.80, 0.85)), 1.4, 3.0),
        TargetCheck("fluke span / BL", summary.fluke_span_bl, 0.22, 0.26),
        TargetCheck("flipper insertion / BL", summary.flipper_insertion_bl, 0.22, 0.25),
        TargetCheck("dorsal fin base start / BL", summary.dorsal_fin_base_bl[0], 0.40, 0.45),
        TargetCheck("dorsal fin base end / BL", summary.dorsal_fin_base_bl[1], 0.52, 0.57),
    ]
