"""Foreign bodies, supersampled frames and H.264: what the held-out split is rendered with."""

import json
from dataclasses import replace

import numpy as np
import pytest
import torch
from scipy.interpolate import PchipInterpolator

from dolphinfit.app.cli import main
from dolphinfit.core.bench.held_out import HELD_OUT
from dolphinfit.core.bench.suites import scenarios
from dolphinfit.core.errors import InputError
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.io.masks import read_png_folder
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.model.hw_from_model import station_extents
from dolphinfit.core.measure.mesh import body_length
from dolphinfit.core.measure.stations import STATION_FRACTIONS
from dolphinfit.core.model.template import load_template
from dolphinfit.core.synth.animal import synth_animal
from dolphinfit.core.synth.clip import make_clip
from dolphinfit.core.synth.config import BODIES, Effects, SynthConfig
from dolphinfit.core.synth.foreign import FOREIGN_BODIES, foreign_template

SMALL = SynthConfig(seed=3, width_px=320, height_px=240, fps=5.0, duration_s=0.4,
                    altitude_m=6.0, length_m=2.3, heading_deg=30.0, speed_m_s=1.0,
                    dive_depth_m=0.0, colouration="light_grey",
                    effects=Effects(profile_warp=False, ripples=False, glints=False))


def _extents(template):
    return station_extents(template.verts, template.station_rings)


def _fin_reach(template, joint: str, axis: int) -> float:
    fin = template.verts[template.fin_vertices[joint]]
    base = template.verts[template.fin_bases[joint]].mean(0)
    return float(np.abs(fin[:, axis] - base[axis]).max())


@pytest.mark.parametrize("name", list(FOREIGN_BODIES))
def test_a_foreign_body_has_its_own_profile_and_fins_at_the_templates_length(name):
    """Widths at the stations are the template's times the body's knots' curve, heights
    times both curves; the tip, the notch and the rings stay where they were; fins scale."""
    template = load_template()
    body = FOREIGN_BODIES[name]
    foreign = foreign_template(template, name)
    width, height = _extents(template)
    foreign_width, foreign_height = _extents(foreign)
    width_factor = PchipInterpolator(*zip(*body.width_knots))(STATION_FRACTIONS)
    height_factor = PchipInterpolator(*zip(*body.height_knots))(STATION_FRACTIONS)
    np.testing.assert_allclose(foreign_width / width, width_factor, rtol=0.02)
    np.testing.assert_allclose(foreign_height / height, width_factor * height_factor,
                               rtol=0.02)
    assert np.ptp(foreign_width / width) > 0.1          # not a uniform rescaling
    lengths = [body_length(torch.as_tensor(t.verts), t.rostrum_idx, t.notch_idx)
               for t in (template, foreign)]
    assert float(lengths[1]) == pytest.approx(float(lengths[0]), abs=1e-12)
    assert _fin_reach(foreign, "fluke_l", 1) == pytest.approx(
        body.fluke_span * _fin_reach(template, "fluke_l", 1), rel=1e-6)
    assert _fin_reach(foreign, "flipper_r", 0) == pytest.approx(
        body.flipper_scale * _fin_reach(template, "flipper_r", 0), rel=1e-6)


def test_the_template_body_is_the_template_and_every_body_is_named():
    template = load_template()
    assert foreign_template(template, "template") is template
    assert BODIES == ("template", *FOREIGN_BODIES)
    with pytest.raises(InputError, match="synth option body: one of template, robust"):
        replace(SMALL, body="blobby")


def test_supersampled_h264_clip_is_delivered_at_its_frame_size_with_matching_masks(tmp_path):
    """Rendered at 3× and downscaled, the H.264 clip decodes at the delivered size; its true
    masks cover what the same scene rendered at that size covers, and the animal stays the
    configured one."""
    plain = make_clip(SMALL, tmp_path / "plain")
    fine = replace(SMALL, supersample=3, codec="h264", bitrate_mbps=2.0)
    files = make_clip(fine, tmp_path / "fine")
    clip = open_clip(files.video)
    assert (clip.width_px, clip.height_px, clip.num_frames) == (320, 240, SMALL.num_frames)
    with VideoReader(clip) as frames:
        assert frames.frame(0).shape == (240, 320, 3)
    ours, theirs = (read_png_folder(f.masks_dir) for f in (files, plain))
    assert ours.stack().shape == theirs.stack().shape == (SMALL.num_frames, 240, 320)
    for t in range(SMALL.num_frames):
        assert mask_iou(ours.mask(t), theirs.mask(t)) > 0.9
    truth = [json.loads(f.truth_json.read_text()) for f in (files, plain)]
    assert truth[0]["volume_m3"] == pytest.approx(truth[1]["volume_m3"], rel=1e-9)
    assert truth[0]["config"]["supersample"] == 3 and truth[0]["config"]["codec"] == "h264"


def test_synth_options_refuse_bad_codecs_and_sizes(capsys):
    with pytest.raises(InputError, match="codec: one of mp4v, h264"):
        replace(SMALL, codec="vp9")
    with pytest.raises(InputError, match="supersample: a whole number in 1–8"):
        replace(SMALL, supersample=0)
    with pytest.raises(InputError, match="bitrate_mbps: must be positive"):
        replace(SMALL, bitrate_mbps=0.0)
    assert main(["synth", "/nonexistent/x", "--body", "blobby"]) == 2
    assert "body: one of" in capsys.readouterr().err


def test_the_held_out_split_shares_nothing_tuned_with_the_tuning_split():
    """Foreign bodies and H.264 throughout, its own cache folder, waters and seeds the tuning
    split never uses, and two clips of 8–15 px wide animals from 5K frames at 720p."""
    tuning = scenarios()
    assert scenarios(split="held-out") == HELD_OUT
    assert {s.suite for s in HELD_OUT}.isdisjoint({s.suite for s in tuning})
    assert {s.config.seed for s in HELD_OUT}.isdisjoint({s.config.seed for s in tuning})
    assert all(s.config.body != "template" and s.config.codec == "h264" for s in HELD_OUT)
    tuning_waters = {s.config.water_rgb for s in tuning}
    assert sum(s.config.water_rgb not in tuning_waters for s in HELD_OUT) >= 4
    small = [s.config for s in HELD_OUT if s.config.supersample > 1]
    assert len(small) == 2
    for config in small:
        assert (config.width_px * config.supersample, config.height_px) == (5120, 720)
        _, model, betas = synth_animal(config, np.random.default_rng(config.seed))
        with torch.no_grad():
            rest = model.forward_rest(betas)[0].numpy()
        width_m = station_extents(rest, model.station_rings.numpy())[0].max()
        focal_px = CameraIntrinsics.from_sensor(config.focal_mm, config.sensor_width_mm,
                                                config.width_px, config.height_px).focal_px
        assert 8.0 <= width_m * focal_px / config.altitude_m <= 15.0
