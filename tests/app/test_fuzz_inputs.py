"""Bad inputs of every class, for every command: exit 2, no traceback, a message naming the
file or option, and every output written before the run still there, byte for byte.

Classes: physically impossible values (altitude, focal length, pixel size, body length,
widths, mass model), thread counts, time windows, configuration files with wrong types or
negative sizes, output paths that are a file or lie under one, truncated .npz files, binary
junk where a CSV or JSON is expected, and empty or all-white masks. Commands run in-process
through app.cli.main; one subprocess checks the installed entry point the same way.
"""

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.app.cli import SUBCOMMANDS, main
from dolphinfit.core.camera_presets import CONFIG_DIR_ENV, DEFAULT_PRESET
from dolphinfit.core.runtime import THREADS_ENV

DATA = Path(__file__).resolve().parents[1] / "data"
MMX = DATA / "morphometrix" / "mmx_v2_demo-annotated.csv"
SRT = DATA / "srt" / "mavic_pro.SRT"
NUM_FRAMES, WIDTH_PX, HEIGHT_PX = 6, 64, 48
JUNK = bytes(range(256)) * 8  # binary junk: every byte value, NUL included


def _write_clip(path: Path) -> None:
    """A dark ellipse on blue-green water, lossless."""
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"FFV1"), 25.0,
                             (WIDTH_PX, HEIGHT_PX))
    for t in range(NUM_FRAMES):
        frame = np.full((HEIGHT_PX, WIDTH_PX, 3), (120, 104, 38), np.uint8)
        cv2.ellipse(frame, (20 + 3 * t, 24), (12, 4), 0, 0, 360, (60, 60, 60), -1)
        writer.write(frame)
    writer.release()


def _mask_folder(path: Path, value: int | None) -> Path:
    """One PNG per frame: all ``value`` (0 empty, 255 all white), or an ellipse (None)."""
    path.mkdir()
    for t in range(NUM_FRAMES):
        mask = np.full((HEIGHT_PX, WIDTH_PX), value or 0, np.uint8)
        if value is None:
            cv2.ellipse(mask, (20 + 3 * t, 24), (12, 4), 0, 0, 360, 255, -1)
        cv2.imwrite(str(path / f"{t:06d}.png"), mask)
    return path


def _annotation(altitude_m: float) -> dict:
    """A straight 2.5 m dolphin 455 px long, explicit camera, at ``altitude_m``."""
    stations = [{"station_pct": pct, "side_a_px": [400 + 4.55 * pct, 340.0],
                 "side_b_px": [400 + 4.55 * pct, 380.0]} for pct in range(5, 100, 5)]
    return {"schema_version": 1, "image": {"image_id": "f0", "media_path": "", "frame_idx": 0},
            "camera": {"focal_mm": 12.29, "sensor_width_mm": 4.3175, "image_width_px": 1280,
                       "image_height_px": 720},
            "altitude": {"altitude_m": altitude_m, "source": "laser"},
            "midline_px": [[400.0, 360.0], [855.0, 360.0]], "mirror_side": None,
            "stations": stations, "notes": ""}


def _write(path: Path, content: str | bytes | dict) -> Path:
    if isinstance(content, dict):
        content = json.dumps(content)  # NaN and Infinity come out as JSON's extensions
    if isinstance(content, str):
        content = content.encode("utf-8")
    path.write_bytes(content)
    return path


@pytest.fixture(scope="module")
def paths(tmp_path_factory) -> dict[str, Path]:
    """Every input and pre-existing output the cases name, by placeholder."""
    root = tmp_path_factory.mktemp("fuzz")
    p: dict[str, Path] = {"missing": root / "missing.mp4", "srt": SRT}
    p["clip"] = root / "clip.mkv"
    _write_clip(p["clip"])
    p["masks"] = _mask_folder(root / "masks", None)
    p["white"] = _mask_folder(root / "white", 255)
    p["empty"] = _mask_folder(root / "empty", 0)
    p["first_half"] = _mask_folder(root / "first_half", None)
    for t in range(3, NUM_FRAMES):
        cv2.imwrite(str(p["first_half"] / f"{t:06d}.png"), np.zeros((HEIGHT_PX, WIDTH_PX)))
    masks = np.stack([cv2.imread(str(p["masks"] / f"{t:06d}.png"), 0) for t in range(6)])
    np.savez_compressed(root / "full.npz", masks=masks)
    p["truncated_npz"] = _write(root / "truncated.npz",
                                (root / "full.npz").read_bytes()[:200])
    p["junk_csv"] = _write(root / "junk.csv", JUNK)
    p["junk_json"] = _write(root / "junk.json", JUNK)
    p["altitudes_1e6"] = _write(root / "alt_1e6.csv",
                                "frame,altitude_m\n" + "".join(f"{t},1e6\n" for t in range(6)))
    p["altitude_text"] = _write(root / "alt_text.csv", "time_s,altitude_m\n0,twenty\n")
    p["fit_config_text"] = _write(root / "fit_text.json", {"fps": "five"})
    p["fit_config_negative"] = _write(root / "fit_negative.json", {"steps_global": -5})
    p["fit_config_nan"] = _write(root / "fit_nan.json", {"weights": {"mask": math.nan}})
    p["fit_config_hw_model"] = _write(root / "fit_hw_model.json", {"hw_table": "model"})
    p["fit_config_hw_nope"] = _write(root / "fit_hw_nope.json", {"hw_table": "nope"})
    p["synth_config_text"] = _write(root / "synth_text.json", {"altitude_m": "high"})
    p["synth_config_negative"] = _write(root / "synth_negative.json",
                                        {"config": {"width_px": -640}})
    p["lens_4k"] = _write(root / "lens_4k.json", {
        "format": "dolphinfit-lens", "version": 1, "width_px": 3840, "height_px": 2160,
        "fx_px": 2900.0, "fy_px": 2900.0, "cx_px": 1919.5, "cy_px": 1079.5,
        "distortion": [-0.1, 0.02, 0.0, 0.0, 0.0], "rms_px": 0.3, "num_views": 12,
        "source": "test"})
    p["mass_nan"] = _write(root / "mass_nan.json", {"density_intercept_kg_m3": math.nan})
    p["mass_text"] = _write(root / "mass_text.json", {"bv_exp_slope": "steep"})
    p["ann"] = _write(root / "ann.json", _annotation(20.0))
    p["ann_1e6"] = _write(root / "ann_1e6.json", _annotation(1e6))
    mmx = MMX.read_text(encoding="utf-8")
    for name, old, new in (("mmx_focal0", "Focal Length,50.0", "Focal Length,0"),
                           ("mmx_pixel0", "Pixel Dimension,0.00391667", "Pixel Dimension,0"),
                           ("mmx_altitude_negative", "Altitude,50.0", "Altitude,-50"),
                           ("mmx_wide", "TL_w50.0,292.7,Pixels", "TL_w50.0,9999,Pixels"),
                           ("mmx_length0", "TL,2034.0,Pixels", "TL,0,Pixels")):
        assert old in mmx
        p[name] = _write(root / f"{name}.csv", mmx.replace(old, new))
    p["file"] = _write(root / "a_file.txt", "an existing file")
    p["under_file"] = p["file"] / "sub"
    p["folder"] = root / "a_folder"
    p["folder"].mkdir()
    p["foreign"] = root / "foreign"
    p["foreign"].mkdir()
    _write(p["foreign"] / "clip.mp4", "the user's own file")
    # pre-existing outputs, which no failed run may touch
    p["out_fit"] = root / "out_fit"
    p["out_fit"].mkdir()
    _write(p["out_fit"] / "result.json", '{"old": true}')
    p["out_measure"] = root / "out_measure"
    p["out_measure"].mkdir()
    _write(p["out_measure"] / "ann_measure.json", '{"old": true}')
    p["out_masks"] = _mask_folder(root / "out_masks", None)
    p["out_csv"] = _write(root / "out.csv", "time_s,altitude_m\n0,20\n")
    p["out_ply"] = _write(root / "out.ply", "old mesh")
    p["out_synth"] = root / "out_synth"
    p["out_synth"].mkdir()
    _write(p["out_synth"] / "truth.json", '{"old": true}')
    p["config_dir"] = root / "config"
    p["config_dir"].mkdir()
    _write(p["config_dir"] / "cameras.json", {"schema_version": 1, "presets": []})
    p["broken_config_dir"] = root / "broken_config"
    p["broken_config_dir"].mkdir()
    _write(p["broken_config_dir"] / "cameras.json", '{"schema_version": 1, "presets": [')
    return p


OUTPUTS = ("out_fit", "out_measure", "out_masks", "out_csv", "out_ply", "out_synth", "file",
           "config_dir", "broken_config_dir")

# (argv with {placeholders}, text the message must hold: the option or file, and the fault)
CASES = [
    # physically impossible values
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 0", "--altitude: 0 m is outside"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude=-5", "--altitude: -5 m"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 1e6", "--altitude: 1e+06 m"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude nan", "--altitude: expected a finite"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude {altitudes_1e6}",
     "alt_1e6.csv: every altitude lies outside the plausible 1–500 m: 1e+06 m at frame 0"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --launch-height nan",
     "--launch-height"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --time-offset inf",
     "--time-offset: expected a finite"),
    ("scan {clip} --out {folder}/scan --launch-height 1e4", "--launch-height: 10000 m"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --lens {lens_4k}",
     "lens_4k.json: the lens was calibrated on 3840×2160 px images; these are 64×48"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --focal-mm 0 "
     "--sensor-width-mm 17.27", "--focal-mm: 0 mm"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --focal-mm 12 "
     "--sensor-width-mm=-1", "--sensor-width-mm: -1 mm"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --fps 0", "--fps: 0 frames/s"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --outline-sd-px=-0.1",
     "--outline-sd-px: -0.1 px is outside"),
    ("measure {mmx_focal0} --out {out_measure}", "mmx_focal0.csv, line 4: Focal Length: 0 mm"),
    ("measure {mmx_pixel0} --out {out_measure}", "mmx_pixel0.csv, line 6: Pixel Dimension"),
    ("measure {mmx_altitude_negative} --out {out_measure}", "line 5: Altitude: -50 m"),
    ("measure {mmx_wide} --out {out_measure}", "mmx_wide.csv: TL: width"),
    ("measure {mmx_length0} --out {out_measure}", "mmx_length0.csv: TL: body length: 0 m"),
    ("measure {ann_1e6} --out {out_measure}", "ann_1e6.json: altitude_m: 1e+06 m"),
    ("measure {ann} --out {out_measure} --altitude-m 0", "--altitude-m: 0 m"),
    ("measure {ann} --out {out_measure} --altitude-m 300", "ann.json: body length: 37.46"),
    ("measure {ann} --out {out_measure} --digitisation-sd-px nan", "--digitisation-sd-px"),
    ("measure {ann} --out {out_measure} --mass-model {mass_nan}",
     "mass_nan.json: mass model density_intercept_kg_m3: expected a finite number"),
    ("measure {ann} --out {out_measure} --mass-model {mass_text}",
     "mass_text.json: mass model bv_exp_slope: expected a number, got 'steep'"),
    ("measure {ann} --out {out_measure} --seed=-1", "--seed: must be at least 0"),
    ("synth {out_synth} --altitude-m 0", "altitude_m: 0 m is outside"),
    ("synth {out_synth} --length-m 80", "length_m: 80 m is outside"),
    ("synth {out_synth} --fps nan", "synth option fps: expected a finite number"),
    ("synth {out_synth} --seed=-3", "synth option seed: must be at least 0"),
    ("camera show " + DEFAULT_PRESET + " --altitude-m 1e6", "--altitude-m: 1e+06 m"),
    ("camera add mine --sensor-width-mm 0 --focal-mm 12 --width-px 1920 --height-px 1080",
     "--sensor-width-mm: 0 mm"),
    ("camera add mine --sensor-width-mm 13 --focal-mm 12 --width-px=-5 --height-px 1080",
     "--width-px: -5 px"),
    ("template export {out_ply} --length 0", "--length: 0 m is outside"),
    ("template export {out_ply} --shape head=nan,0,0,0", "--shape 'head=nan,0,0,0'"),
    ("template export {out_ply} --pose flukes=0,inf,0", "--pose 'flukes=0,inf,0'"),
    ("masks {clip} --seed nan,20 --out {out_masks}", "--seed 'nan,20'"),
    ("masks {clip} --box 10,10,0,8 --out {out_masks}", "--box '10,10,0,8': width"),
    ("masks {clip} --auto --frame=-1 --out {out_masks}", "--frame -1"),
    ("telemetry {srt} --launch-height 1e4 --out {out_csv}", "--launch-height: 10000 m"),
    ("telemetry {srt} --time-offset nan --out {out_csv}", "--time-offset: expected a finite"),
    ("telemetry {altitude_text} --out {out_csv}", "alt_text.csv, line 2: altitude_m 'twenty'"),
    # thread counts, time windows
    ("--threads 0 camera list", "--threads: must be at least 1"),
    ("--threads=-2 fit {clip} --altitude 20 --out {out_fit}", "--threads: must be at least 1"),
    ("--threads two camera list", "--threads"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --start 2 --end 1",
     "--start 2 s is not before --end 1 s"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --start nan", "--start"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --end=-1", "--end: must be at "),
    # configuration files
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --config {fit_config_text}",
     "fit_text.json: fit config: field 'fps': expected a number, got 'five'"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --config {fit_config_negative}",
     "fit_negative.json: fit option steps_global: must be at least 0"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --config {fit_config_nan}",
     "fit_nan.json: fit option weights.mask: expected a finite number"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --config {fit_config_hw_model}",
     "fit_hw_model.json: fit option hw_table: 'model' would take the fit's heights from the"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --config {fit_config_hw_nope}",
     "fit_hw_nope.json: unknown HW ratio preset 'nope'"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --config {junk_json}",
     "junk.json: not valid JSON"),
    ("synth {out_synth} --config {synth_config_text}",
     "synth_text.json: synth config: field 'altitude_m': expected a number, got 'high'"),
    ("synth {out_synth} --config {synth_config_negative}",
     "synth_negative.json: synth option width_px: -640 px is outside"),
    ("synth {out_synth} --config {junk_json}", "junk.json: not valid JSON"),
    ("synth {out_synth} --width-px many", "--width-px"),
    # output paths that are a file or lie under a file
    ("fit {clip} --masks {masks} --altitude 20 --out {file}", "a_file.txt: is a file"),
    ("fit {clip} --masks {masks} --altitude 20 --out {under_file}", "lies under"),
    ("fit {clip} --masks {masks} --altitude 20 --out {foreign}/..", "holds folders"),
    ("demo --out {file}", "--out " + "{file}: is a file"),
    ("measure {ann} --out {file}", "--out {file}: is a file"),
    ("masks {clip} --auto --out {under_file}", "sub: lies under"),
    ("masks {clip} --auto --out {foreign}", "foreign: holds other things than mask PNGs"),
    ("telemetry {srt} --launch-height 2 --out {under_file}/alt.csv", "lies under"),
    ("telemetry {srt} --launch-height 2 --out {folder}", "a_folder: is a folder"),
    ("template export {under_file}/x.ply", "lies under"),
    ("template build --out {under_file}/t.npz", "lies under"),
    ("synth {file}", "a_file.txt: is a file, not a folder"),
    # truncated .npz, binary junk
    ("fit {clip} --masks {truncated_npz} --out {out_fit} --altitude 20",
     "truncated.npz: not a readable .npz file"),
    ("measure {ann} --out {out_measure} --from-mask {truncated_npz}", "truncated.npz"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude {junk_csv}", "junk.csv: "),
    ("measure {junk_csv} --out {out_measure}", "junk.csv"),
    ("measure {ann} --out {out_measure} --hw {junk_csv}", "junk.csv, line 1: expected the"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --hw {junk_csv}",
     "junk.csv, line 1: expected the"),
    ("fit {clip} --masks {masks} --out {out_fit} --altitude 20 --hw tursiops-fat",
     "--hw: unknown HW ratio preset 'tursiops-fat'"),
    ("telemetry {junk_csv} --out {out_csv}", "junk.csv: cannot be read as CSV"),
    ("masks {junk_csv} --auto --out {out_masks}", "junk.csv"),
    ("fit {junk_csv} --altitude 20 --out {out_fit}", "junk.csv"),
    ("template info --path {junk_csv}", "junk.csv"),
    # empty or all-white masks
    ("fit {clip} --masks {white} --out {out_fit} --altitude 20",
     "white: 6 mask(s) cover more than 90% of the frame (all white or inverted; non-zero "
     "pixels are dolphin): 000000.png, 000001.png"),
    ("fit {clip} --masks {empty} --out {out_fit} --altitude 20",
     "empty: all 6 masks are empty (frames 0–5)"),
    ("fit {clip} --masks {first_half} --out {out_fit} --altitude 20 --start 0.12 --fps 25",
     "no frame with a visible dolphin in the chosen range (3 frames looked at; png folder "
     "{first_half}: empty masks in frames 3, 4, 5)"),
    ("measure {ann} --out {out_measure} --from-mask {white}", "white: 6 mask(s) cover"),
    # missing files and commands
    ("fit {missing} --altitude 20 --out {out_fit}", "missing.mp4"),
    ("gui {missing}", "no display"),
    ("", "COMMAND"),
    ("fly", "invalid choice: 'fly'"),
]


def _snapshot(paths: dict[str, Path]) -> dict[str, bytes]:
    """Every file of the pre-existing outputs, by path, with its bytes."""
    files = {}
    for name in OUTPUTS:
        root = paths[name]
        for path in [root] if root.is_file() else sorted(root.rglob("*")):
            files[str(path)] = path.read_bytes() if path.is_file() else b"<folder>"
    return files


def run_cli(argv: list[str], capsys) -> tuple[int, str]:
    """Exit code and stderr of ``dolphinfit ARGV`` run in-process (argparse's own errors
    arrive as SystemExit)."""
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    return code, capsys.readouterr().err


@pytest.mark.parametrize("case", CASES, ids=[c[0].split(" {")[0] + f" #{i}"
                                               for i, c in enumerate(CASES)])
def test_bad_input_exits_2_naming_it_and_keeps_old_outputs(case, paths, capsys, monkeypatch):
    """Exit 2, no traceback, the option or file and the fault named, old outputs intact."""
    template, expected = case
    monkeypatch.setenv(CONFIG_DIR_ENV, str(paths["config_dir"]))
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.delenv("QT_QPA_PLATFORM", raising=False)
    fill = {name: str(path) for name, path in paths.items()}
    argv = [arg.format(**fill) for arg in template.split()]
    before = _snapshot(paths)
    code, err = run_cli(argv, capsys)
    assert code == 2, err
    assert "Traceback" not in err
    assert expected.format(**fill) in err
    assert _snapshot(paths) == before


def test_broken_user_presets_file_is_named_and_kept(paths, capsys, monkeypatch):
    """`camera add` over a truncated user presets file exits 2 naming it, and keeps it."""
    monkeypatch.setenv(CONFIG_DIR_ENV, str(paths["broken_config_dir"]))
    before = _snapshot(paths)
    code, err = run_cli("camera add mine --sensor-width-mm 13 --focal-mm 12 --width-px 1920 "
                        "--height-px 1080".split(), capsys)
    assert code == 2 and "Traceback" not in err
    assert f"{paths['broken_config_dir'] / 'cameras.json'}: not valid JSON" in err
    assert _snapshot(paths) == before


@pytest.mark.parametrize("text", ["0", "-1", "many", "2.5"])
def test_bad_thread_variable_exits_2_naming_it(text, paths, capsys, monkeypatch):
    """$DOLPHINFIT_THREADS that is no whole number ≥ 1 is refused like the flag."""
    monkeypatch.setenv(THREADS_ENV, text)
    code, err = run_cli(["camera", "show", DEFAULT_PRESET], capsys)
    assert code == 2 and f"${THREADS_ENV}" in err and "Traceback" not in err


@pytest.mark.parametrize("name", [None, *sorted(SUBCOMMANDS), "camera list", "camera show",
                                  "camera add", "template build", "template info",
                                  "template export"])
def test_help_of_every_command(name, capsys):
    """`dolphinfit --help` and each subcommand's --help print their usage and exit 0."""
    argv = [] if name is None else name.split()
    with pytest.raises(SystemExit) as exit_info:
        main([*argv, "--help"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.startswith(f"usage: dolphinfit {' '.join(argv)}".rstrip())


def test_installed_entry_point_exits_2_without_traceback(paths):
    """The real process: an impossible altitude exits 2 with one line naming the option."""
    done = subprocess.run([sys.executable, "-m", "dolphinfit.app.cli", "fit", str(paths["clip"]),
                           "--altitude", "0", "--out", str(paths["out_fit"])],
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, THREADS_ENV: "1"})
    assert done.returncode == 2
    assert done.stderr.strip() == ("dolphinfit: error: --altitude: 0 m is outside the "
                                   "plausible range 1–500 m")
