"""A fit knows what it was made from: the clip's camera, altitude, altitude calibration, lens
and masks; it says which changed since, not a rebased path; the project file keeps it."""

from dataclasses import replace

from dolphinfit.core.measure.lens import LensModel
from dolphinfit.core.project.fit_inputs import changed_since_fit, fit_inputs_of, stale_note
from dolphinfit.core.project.model import AltitudeSpec, with_animal, with_clip
from dolphinfit.core.project.project_file import read_project, rebase_media, write_project

from .test_calibrations import calibration_set


def _fitted(project):
    """The project with its first animal's fit made from the clip as it is."""
    clip = project.clips[0]
    animal = replace(clip.animals[0], fit_inputs=fit_inputs_of(project, clip))
    return with_animal(project, 0, 0, animal)


def _changed(project, **clip_changes):
    changed = with_clip(project, 0, replace(project.clips[0], **clip_changes))
    return changed_since_fit(changed, changed.clips[0], changed.clips[0].animals[0])


def test_a_fit_names_each_input_changed_since(project, camera):
    fitted = _fitted(project)
    clip = fitted.clips[0]
    assert changed_since_fit(fitted, clip, clip.animals[0]) == []
    assert _changed(fitted, camera=replace(camera, focal_mm=13.0)) == ["camera"]
    assert _changed(fitted, camera=replace(camera, description="renamed")) == []
    assert _changed(fitted, altitude=AltitudeSpec(constant_m=19.0, source="laser")) == \
        ["altitude"]
    lens = LensModel(1280, 720, 900.0, 900.0, 640.0, 360.0, (-0.1, 0.0, 0.0, 0.0, 0.0), 0.3,
                     9, "a lens")
    assert _changed(fitted, lens=lens, masks_path="media/other_masks") == ["lens", "masks"]
    calibrated = replace(fitted, calibrations=(calibration_set(camera),))
    named = with_clip(calibrated, 0, replace(calibrated.clips[0],
                                             altitude_calibration=calibrated.calibrations[0].name))
    assert changed_since_fit(named, named.clips[0], named.clips[0].animals[0]) == \
        ["altitude calibration"]
    assert stale_note(["camera", "lens"]).startswith(
        "⚠ out of date: the clip's camera, lens changed since this fit")
    assert stale_note([]) == ""


def test_a_fit_from_before_inputs_were_kept_or_no_fit_is_never_out_of_date(project, camera):
    assert project.clips[0].animals[0].fit_inputs == ()
    assert _changed(project, camera=replace(camera, focal_mm=13.0)) == []
    unfitted = with_animal(_fitted(project), 0, 0,
                           replace(_fitted(project).clips[0].animals[0], fit_path=None))
    clip = replace(unfitted.clips[0], camera=replace(camera, focal_mm=13.0))
    assert changed_since_fit(unfitted, clip, clip.animals[0]) == []


def test_the_project_file_keeps_it_and_save_as_does_not_make_it_stale(tmp_path, project):
    fitted = _fitted(project)
    write_project(tmp_path / "survey.dolphinfit", fitted)
    back = read_project(tmp_path / "survey.dolphinfit")
    assert back.clips[0].animals[0].fit_inputs == fitted.clips[0].animals[0].fit_inputs
    moved = rebase_media(back, tmp_path, tmp_path / "out" / "deeper")
    assert moved.clips[0].masks_path != back.clips[0].masks_path
    assert changed_since_fit(moved, moved.clips[0], moved.clips[0].animals[0]) == []
