"""Clips drawn by VTK: the same scene as dolphinfit's renderer draws for a configuration, other
pixels, and true masks that are the geometry's."""

import json
from dataclasses import replace

import cv2
import numpy as np
import pytest
import torch

from dolphinfit.core.bench import scenario as scenarios
from dolphinfit.core.bench.scenario import Scenario, ensure_scenario
from dolphinfit.core.bench.vtk_split import VTK_RENDERER, VTK_SPLIT
from dolphinfit.core.camera import NadirCamera
from dolphinfit.core.errors import InputError
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.render.rasterize import rasterize
from dolphinfit.core.render.render import project_to_viewport
from dolphinfit.core.render.settings import Viewport
from dolphinfit.core.segment.evaluate import outline_offset_px
from dolphinfit.core.synth.animal import swimming_animal
from dolphinfit.core.synth.clip import make_clip
from dolphinfit.core.synth.config import Effects, SynthConfig
from dolphinfit.core.synth.files import made_from, read_part_masks
from dolphinfit.vtk_clips.clip import make_vtk_clip

SMALL = SynthConfig(seed=13, width_px=320, height_px=240, fps=5.0, duration_s=0.6,
                    altitude_m=6.0, length_m=2.3, heading_deg=30.0, speed_m_s=1.0,
                    noise_sd=0.0, blur_px=0.0, glitter=0.3, sea_state=0.3,
                    effects=Effects(compression=False))


@pytest.fixture(scope="module")
def vtk_clip(tmp_path_factory):
    return make_vtk_clip(SMALL, tmp_path_factory.mktemp("vtk"))


def _exact_masks(config: SynthConfig, points: int = 8) -> np.ndarray:
    """(T, H, W) the pixels at least half covered by the clip's animal, counted on
    ``points`` × ``points`` a pixel by dolphinfit's own rasterizer."""
    animal = swimming_animal(config, np.random.default_rng(config.seed))
    fine = CameraIntrinsics.from_sensor(config.focal_mm, config.sensor_width_mm,
                                        config.width_px * points, config.height_px * points)
    camera = NadirCamera(fine, torch.as_tensor(animal.altitude_m), refraction=False)
    xy, depth = project_to_viewport(animal.verts.double(), camera,
                                    Viewport.full_frame(fine, len(animal.altitude_m)))
    covered = rasterize(xy, depth, animal.model.faces, fine.height_px, fine.width_px,
                        10**8).covered.numpy()
    return covered.reshape(len(covered), config.height_px, points, config.width_px,
                           points).mean((2, 4)) >= 0.5


def test_the_true_masks_are_the_geometry_s(vtk_clip):
    """VTK's flat views counted 4 × 4 a pixel give the masks dolphinfit's rasterizer gives
    counted 8 × 8: IoU above 0.97, outlines within 0.06 px on average."""
    clip = open_clip(vtk_clip.video)
    exact = _exact_masks(SMALL)
    for t in range(clip.num_frames):
        mask = cv2.imread(str(vtk_clip.masks_dir / f"{t:06d}.png"), cv2.IMREAD_GRAYSCALE) > 0
        iou = (mask & exact[t]).sum() / (mask | exact[t]).sum()
        assert iou > 0.97
        assert abs(outline_offset_px(mask, exact[t])) < 0.06


def test_the_parts_lie_in_the_mask_and_the_truth_names_vtk(vtk_clip):
    parts = read_part_masks(vtk_clip.parts)
    masks = np.stack([cv2.imread(str(path), cv2.IMREAD_GRAYSCALE) > 0
                      for path in sorted(vtk_clip.masks_dir.glob("*.png"))])
    for name in ("flukes", "rostrum"):
        assert parts[name].any(axis=(1, 2)).all()
        assert not (parts[name] & ~masks).any()
    truth = json.loads(vtk_clip.truth_json.read_text())
    assert truth["renderer"] == VTK_RENDERER
    assert all(frame["visible"] for frame in truth["frames"])
    assert made_from(vtk_clip, SMALL, VTK_RENDERER)
    assert not made_from(vtk_clip, SMALL)         # not dolphinfit's own clip


def test_the_same_scene_in_other_pixels(vtk_clip, tmp_path):
    """Dolphinfit's renderer draws the same animal in the same place (the masks agree to an IoU
    above 0.9: its own refraction and ripples move the outline a little) in pixels of its own
    (a mean difference of more than 5 grey levels inside the animal: 9 in this scene)."""
    own = make_clip(SMALL, tmp_path)
    with VideoReader(open_clip(vtk_clip.video)) as vtk_frames, \
            VideoReader(open_clip(own.video)) as own_frames:
        for t in range(len(vtk_frames)):
            vtk_mask = cv2.imread(str(vtk_clip.masks_dir / f"{t:06d}.png"), 0) > 0
            own_mask = cv2.imread(str(own.masks_dir / f"{t:06d}.png"), 0) > 0
            assert (vtk_mask & own_mask).sum() / (vtk_mask | own_mask).sum() > 0.9
            difference = np.abs(vtk_frames[t].astype(float) - own_frames[t].astype(float))
            assert difference[vtk_mask].mean() > 5


def test_a_vtk_scenario_needs_its_renderer_loaded(monkeypatch, tmp_path):
    monkeypatch.setenv("DOLPHINFIT_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(scenarios, "_RENDERERS", {})
    with pytest.raises(InputError, match="import dolphinfit.vtk_clips"):
        ensure_scenario(Scenario("x", SMALL, "a test", "vtk-test", VTK_RENDERER))


def test_the_vtk_split_is_drawn_by_vtk_alone():
    assert len(VTK_SPLIT) == 8
    assert {scenario.renderer for scenario in VTK_SPLIT} == {VTK_RENDERER}
    assert len({scenario.config.seed for scenario in VTK_SPLIT}) == 8
    assert all(replace(s.config).codec == "h264" for s in VTK_SPLIT)
