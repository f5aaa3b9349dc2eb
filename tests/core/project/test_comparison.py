"""The comparison CSV (core/project/comparison.py) as File → Export → Comparison writes it: one
row per animal with a saved 3D fit and a measured frame, both methods' figures with their 95 %
intervals and their difference, joinable on ``Image_ID``; nothing to compare, no file.

The fit is the template itself, saved as a fit of two frames that stopped early: its figures
are the template's, and the row must carry them."""

import csv
from dataclasses import replace

import numpy as np
import pytest
import torch

from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.result import STATUS_CANCELLED, FitResult
from dolphinfit.core.fit.result_io import write_fit_result
from dolphinfit.core.measure.condition import body_condition
from dolphinfit.core.measure.mesh import body_length, mesh_volume
from dolphinfit.core.model.template import load_template
from dolphinfit.core.project.comparison import project_comparison_rows, write_comparison_csv
from dolphinfit.core.project.evaluate import frame_results
from dolphinfit.core.project.model import MeasurementKey

from .conftest import write_black_clip

NUM_DRAWS = 200


def _template_fit() -> FitResult:
    """The template as a fitted animal in two frames (3 and 7), cancelled after its first
    stage, with the figures a fit computes from its rest mesh."""
    template = load_template()
    verts, faces = template.verts, template.faces
    volume = float(mesh_volume(torch.as_tensor(verts), torch.as_tensor(faces)))
    length = float(body_length(torch.as_tensor(verts), template.rostrum_idx, template.notch_idx))
    condition = body_condition(np.float64(length), np.float64(volume))
    parts, frames = len(template.group_names), np.array([3, 7])
    transl = np.array([[0.0, 0.0, -0.3], [0.4, 0.1, -0.3]])
    return FitResult(
        betas=np.zeros((parts, 4)), pose_aa=np.zeros((2, parts, 3)), transl=transl,
        frame_idx=frames, time_s=frames / 10.0, iou=np.array([0.8, 0.82]), rest_verts=verts,
        posed_verts=verts[None] + transl[:, None], faces=faces,
        albedo=template.albedo / 255.0, f_water=np.array([0.2, 0.5, 0.6]),
        light={"axes": np.eye(3)[:1], "sharpness": np.ones(1), "amplitude": np.ones((1, 3))},
        volume_m3=volume, length_m=length, bci=float(condition.bci),
        mass_kg=float(condition.mass_kg), density_kg_m3=float(condition.density_kg_m3),
        loss_history=(), timings_s={}, config=FitConfig(), warnings=(),
        status=STATUS_CANCELLED, status_message="cancelled by the user after 3 of 96 steps")


def _survey(tmp_path, project):
    """The project's clip as a 10-frame video beside its file and dolphin 1's fit saved where
    its ``fit_path`` says; the project's path."""
    write_black_clip(tmp_path / "media")
    path = tmp_path / "p.dolphinfit"
    write_fit_result(_template_fit(), path.parent / project.clips[0].animals[0].fit_path)
    return path


def _read_csv(path) -> tuple[list[str], list[dict[str, str]]]:
    with path.open(newline="", encoding="utf-8") as file:
        reader = csv.DictReader(file)
        return list(reader.fieldnames), list(reader)


def test_one_row_per_animal_with_a_fit_and_a_measured_frame(tmp_path, project):
    """Dolphin 1 (fitted, measured on frames 3 and 7) gets one row from its first measured
    frame, with the saved fit's status and figures inside the fit's interval; dolphin 2 (no
    fit) is left out, saying why."""
    path = _survey(tmp_path, project)
    fit = _template_fit()
    rows, notes = project_comparison_rows(project, path, NUM_DRAWS)
    assert notes == ["clip.mp4 dolphin 2: no 3D fit"]
    target = tmp_path / "comparison.csv"
    write_comparison_csv(target, rows)
    columns, (row, *others) = _read_csv(target)
    assert others == []
    assert columns[:11] == ["Image_ID", "animal_id", "fit_status", "fit_out_of_date_because",
                            "length_m_ell", "length_m_ell_lo95", "length_m_ell_hi95",
                            "length_m_fit", "length_m_fit_lo95", "length_m_fit_hi95",
                            "length_m_diff_pct"]
    assert len(columns) == 4 + 5 * 7 and "bci_diff" in columns and "bci_diff_pct" not in columns
    assert (row["Image_ID"], row["animal_id"], row["fit_status"],
            row["fit_out_of_date_because"]) == ("clip_f000003", "dolphin 1", "cancelled", "")
    figures = {key: float(value) for key, value in row.items() if key not in columns[:4]}
    for key in ("length_m", "volume_m3", "bci", "density_kg_m3", "mass_kg"):
        assert figures[f"{key}_fit"] == pytest.approx(getattr(fit, key), rel=1e-12), key
        for method in ("ell", "fit"):
            low, value, high = (figures[f"{key}_{method}{end}"] for end in ("_lo95", "", "_hi95"))
            assert low < value < high, (key, method)
    assert figures["volume_m3_fit"] == fit.volume_m3
    # the elliptical side is the frame's own estimate; the difference is the fit's minus it
    (measured,), _ = frame_results(project, path, [MeasurementKey(0, 0, 0)], NUM_DRAWS)
    elliptical = measured.record["volume_m3"]
    assert figures["volume_m3_ell"] == pytest.approx(elliptical, rel=1e-12)
    assert figures["volume_m3_diff_pct"] == pytest.approx(
        100 * (fit.volume_m3 - elliptical) / elliptical, rel=1e-12)
    assert figures["bci_diff"] == pytest.approx(figures["bci_fit"] - figures["bci_ell"],
                                                abs=1e-12)


def test_nothing_to_compare_without_a_measured_frame(tmp_path, project):
    """A fit but no measured frame: no row, the animal noted as not measured, and writing
    the CSV is an input error that writes nothing."""
    path = _survey(tmp_path, project)
    clip = project.clips[0]
    unmeasured = replace(project, clips=(replace(clip, animals=(
        replace(clip.animals[0], measurements=()), *clip.animals[1:])),))
    rows, notes = project_comparison_rows(unmeasured, path, NUM_DRAWS)
    assert rows == []
    assert notes == ["clip.mp4 dolphin 1: not measured", "clip.mp4 dolphin 2: no 3D fit"]
    target = tmp_path / "comparison.csv"
    with pytest.raises(InputError, match="nothing to compare"):
        write_comparison_csv(target, rows)
    assert not target.exists()


def test_a_fit_made_before_the_clips_camera_changed_says_so_in_its_row(tmp_path, project):
    from dolphinfit.core.project.fit_inputs import fit_inputs_of
    from dolphinfit.core.project.model import with_animal, with_clip

    clip = project.clips[0]
    fitted = with_animal(project, 0, 0, replace(clip.animals[0],
                                                fit_inputs=fit_inputs_of(project, clip)))
    changed = with_clip(fitted, 0, replace(fitted.clips[0], camera=replace(
        clip.camera, focal_mm=clip.camera.focal_mm + 1.0)))
    path = _survey(tmp_path, changed)
    (row,), _ = project_comparison_rows(changed, path, NUM_DRAWS)
    assert row["fit_out_of_date_because"] == "camera"
