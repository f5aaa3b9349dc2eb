"""Benchmark plumbing: timing, memory measurement, floor, dense sizing and the CLI."""

import json

from dataclasses import asdict, replace

import pytest
import torch

from dolphinfit.app.cli import build_parser, main
from dolphinfit.core.bench import render_bench
from dolphinfit.core.errors import InputError
from dolphinfit.core.bench.timing import median_ms, median_phases_ms, peak_rss_mb_of


def allocate_job(megabytes: int):
    """Set-up for the memory test: a job that allocates and touches ``megabytes``."""
    def job():
        block = torch.ones(megabytes * 2**20 // 4)
        return float(block.sum())
    return job


def test_median_ms_takes_the_median(monkeypatch):
    """The median of the timed runs' wall times, the warm-up's left out; a real sleep
    measures at least its length (how much more is the machine's load, not asserted)."""
    import time

    from dolphinfit.core.bench import timing

    clock, durations = [100.0], iter([0.5, 0.002, 0.009, 0.004])   # the first: warm-up

    def run():
        clock[0] += next(durations)

    with monkeypatch.context() as patch:
        patch.setattr(timing.time, "perf_counter", lambda: clock[0])
        assert median_ms(run, repeats=3) == pytest.approx(4.0)       # of 2, 9 and 4 ms
    assert median_ms(lambda: time.sleep(0.005), repeats=3) >= 4.99  # 5 ms, float rounding


def test_phases_are_timed_within_the_same_repeats():
    """Each phase's median comes from the phase's own times; the total is the median of the
    repeats' sums, so no phase can come out negative."""
    samples = iter([(0.002, 0.001), (0.004, 0.003), (0.003, 0.010), (0.001, 0.002)])
    phases, total = median_phases_ms(lambda: next(samples), repeats=3)   # the first: warm-up
    assert phases == pytest.approx([3.0, 3.0])    # medians of (4, 3, 1) and (3, 10, 2) ms
    assert total == pytest.approx(7.0)            # median of the sums 7, 13 and 3 ms


def test_peak_memory_of_a_job_counts_what_it_allocates():
    """A job touching 200 MB adds about 200 MB of peak memory, set-up excluded."""
    added = peak_rss_mb_of(__name__, "allocate_job", 200)
    assert 190 < added < 260


def test_dense_size_respects_the_memory_budget(monkeypatch):
    """The dense reference runs at the largest size whose pairs fit the budget."""
    monkeypatch.setattr(render_bench, "DENSE_MEMORY_FRACTION", 1e-12)
    assert render_bench.dense_size(8000) == render_bench.DENSE_SIZES[-1]
    monkeypatch.setattr(render_bench, "DENSE_MEMORY_FRACTION", 1e9)
    assert render_bench.dense_size(8000) == render_bench.DENSE_SIZES[0]


def test_bench_render_quick_reports_consistent_ratios(capsys):
    """`bench render --quick --json` gives positive figures and ratios that match them."""
    assert main(["bench", "render", "--quick", "--repeats", "1", "--json"]) == 0
    figures = json.loads(capsys.readouterr().out)
    for key in ("paper_ms", "paper_floor_ms", "roi_ms", "dense_ms", "peak_memory_mb",
                "paper_forward_ms", "paper_backward_ms", "roi_forward_ms", "roi_backward_ms",
                "roi_faces_ms"):
        assert figures[key] > 0
    assert figures["roi_faces_ratio_vs_floor"] == pytest.approx(figures["roi_faces_ms"]
                                                                / figures["roi_floor_ms"])
    assert figures["ratio_vs_floor"] == pytest.approx(figures["paper_ms"]
                                                      / figures["paper_floor_ms"])
    assert figures["speedup_vs_dense"] == pytest.approx(figures["dense_ms"]
                                                        / figures["sparse_ms_at_dense_size"])
    assert figures["speedup_vs_dense"] > 1
    assert figures["paper_covered_px"] > 300
    # the run's record: the bench and options that made the figures, and the threads
    assert figures["run"]["bench"] == "render"
    assert figures["run"]["options"] == {"repeats": 1, "quick": True}
    assert figures["run"]["torch_threads"] >= 1


@pytest.fixture(scope="module")
def tiny_scenario(tmp_path_factory):
    """A one-scenario suite of a small light-grey clip over green water, rendered once into
    a cache of this module's own."""
    from dolphinfit.core.bench.scenario import Scenario, ensure_scenario
    from dolphinfit.core.synth import sample
    from dolphinfit.core.synth.config import SynthConfig
    from dolphinfit.core.synth.water import with_water

    with pytest.MonkeyPatch.context() as patch:
        patch.setenv(sample.CACHE_DIR_ENV, str(tmp_path_factory.mktemp("cache")))
        tiny = with_water(SynthConfig(seed=5, width_px=640, height_px=480, fps=5.0,
                                      duration_s=0.8, altitude_m=8.0, dive_depth_m=0.0,
                                      colouration="light_grey",
                                      hw_table="tursiops-provisional"), "green")
        scenario = Scenario("tiny", tiny, "a small light-grey clip")
        ensure_scenario(scenario)
        yield scenario


def test_fit_suite_scores_clips_against_their_truth(tiny_scenario):
    """A one-clip suite with true masks and with the product's own masks from the automatic
    seed reports per-clip errors, per-frame IoU and a summary per variant. (The automatic
    seed ends in a click at the animal its scan picked, so it also runs the click variant's
    path.)"""
    from dolphinfit.core.bench import fit_bench
    from dolphinfit.core.fit.config import FitConfig

    quick = FitConfig(heading_trial_steps=2, steps_global=3, steps_body=2, steps_shape=4)
    variants = ("true_masks", "product_masks_auto_seed")
    figures = fit_bench.bench_suite((tiny_scenario,), variants=variants, base=quick)
    assert [c["variant"] for c in figures["clips"]] == list(variants)
    for clip in figures["clips"]:
        assert abs(clip["volume_error"]) < 0.5 and clip["frames"] >= 3
        # heights drawn from the table the fit assumes, elliptical sections
        assert abs(clip["hidden_height_floor"]) < 0.08
        assert len(clip["frame_iou"]) == clip["frames"]
        assert min(clip["frame_iou"]) == clip["min_iou"] > 0.5
        # the fit's 95 % interval lies around its own value
        assert clip["volume_low_error"] < clip["volume_error"] < clip["volume_high_error"]
    summary = figures["summary"]["true_masks"]
    assert summary["median_abs_volume_error"] == abs(figures["clips"][0]["volume_error"])
    first = figures["clips"][0]
    assert summary["volume_interval_coverage"] == float(
        first["volume_low_error"] <= 0 <= first["volume_high_error"])
    with pytest.raises(InputError, match="variants nope: unknown"):
        fit_bench.bench_suite((tiny_scenario,), variants=("nope",), base=quick)


def test_mask_bench_scores_each_back_end_from_the_click_the_automatic_seed_and_a_box(
        tiny_scenario):
    """The back-ends on the same clip: the network keeps a light-grey animal over green water
    from each seed, and with the colour outline step from a click; the colour tracker, which
    looks for a dark animal, finds none at the click nor by itself and scores 0 with the
    reason recorded, but follows it from a box (GrabCut finds it there)."""
    from dolphinfit.core.bench.mask_bench import bench_masks, score_backend
    from dolphinfit.core.bench.scenario import ensure_scenario

    clip = ensure_scenario(tiny_scenario)
    figures = bench_masks({"tiny": clip}, backends=("network", "colour"), stride=2)
    network, colour = figures["clips"]
    colour_edges = asdict(score_backend("tiny", clip, "network-colour-edges", stride=2))
    assert [network["backend"], colour_edges["backend"]] == ["network", "network-colour-edges"]
    for figures_of in (network, colour_edges):
        assert figures_of["frames"] == 2 and not figures_of["error"]
        assert figures_of["mean_iou"] > 0.85 and figures_of["flukes_iou"] > 0.5
        assert 0.0 <= figures_of["rostrum_iou"] <= 1.0
        assert abs(figures_of["outline_offset_px"]) < 0.6
    assert set(network["seeds"]) == {"auto", "box"}
    assert network["seed_seconds"] > 0 and network["seconds_per_tracked_frame"] > 0
    assert 2 * network["seconds_per_frame"] == pytest.approx(
        network["seed_seconds"] + network["seconds_per_tracked_frame"])   # 2 frames
    for kind in ("auto", "box"):
        assert network["seeds"][kind]["mean_iou"] > 0.85
        assert not network["seeds"][kind]["error"]
    assert colour["mean_iou"] == 0.0 and "no dark, elongated animal" in colour["error"]
    assert colour["seeds"]["auto"]["mean_iou"] == 0.0 and colour["seeds"]["auto"]["error"]
    assert colour["seeds"]["box"]["mean_iou"] > 0.8
    summary = figures["summary"]["network"]
    assert summary["mean_iou"] == network["mean_iou"]
    assert summary["seeds"]["box"]["mean_iou"] == network["seeds"]["box"]["mean_iou"]
    with pytest.raises(InputError, match="seed kind: one of click, auto, box, got 'lasso'"):
        bench_masks({}, seeds=("lasso",))


class _Clocked:
    """A stand-in back-end on a stand-in clock: 3 s to find the animal, then 1 s a frame,
    each frame reported as done; or an InputError after 3 s."""

    def __init__(self, clock: list[float], frames: int, finds: bool = True) -> None:
        self.clock, self.frames, self.finds = clock, frames, finds

    def segment(self, frames, seed, progress=None, cancel=None):
        self.clock[0] += 3.0
        if not self.finds:
            raise InputError("no animal at the seed")
        for done in range(1, self.frames + 1):
            progress(done)
            self.clock[0] += 1.0
        return "masks"


def test_a_pass_is_timed_in_all_and_apart_for_the_seed_and_the_frames_after_it(monkeypatch):
    from dolphinfit.core.bench import mask_bench

    clock = [100.0]
    monkeypatch.setattr(mask_bench.time, "perf_counter", lambda: clock[0])
    track, timed, error = mask_bench.timed_pass(_Clocked(clock, 5), [], None)
    assert (track, error) == ("masks", "")
    assert timed == mask_bench.PassTime(8.0, 3.0) and timed.after_seed_seconds == 5.0
    track, timed, error = mask_bench.timed_pass(_Clocked(clock, 5, finds=False), [], None)
    assert (track, error) == (None, "no animal at the seed")
    assert timed.seconds == 3.0 and timed.seed_seconds != timed.seed_seconds   # NaN


def test_suite_clips_by_name_keep_the_order_given_and_refuse_unknown_names(capsys):
    from dolphinfit.app.commands.bench import _chosen_clips

    args = build_parser("bench").parse_args(
        ["bench", "masks", "--only", "turn_right,small_5k_pair,grey_green"])
    chosen = _chosen_clips(args)
    assert {split: [s.name for s in part] for split, part in chosen.items()} == \
        {"tuning": ["turn_right", "grey_green"], "held-out": ["small_5k_pair"]}
    assert main(["bench", "masks", "--only", "nope"]) == 2
    assert "got 'nope'" in capsys.readouterr().err


def test_the_4k_suite_is_the_same_scenes_with_four_times_the_pixels(capsys):
    from dolphinfit.core.bench.suites import scenarios

    full_hd, uhd = scenarios(), scenarios(frame_size="4k")
    assert [s.name for s in uhd] == [s.name for s in full_hd]
    for small, large in zip(full_hd, uhd, strict=True):
        assert (large.config.width_px, large.config.height_px) == (3840, 2160)
        assert replace(large.config, width_px=1920, height_px=1080) == small.config
        assert large.suite == f"{small.suite}-4k"   # cached apart
    with pytest.raises(InputError, match="suite frame size: one of 1080p, 4k"):
        scenarios(frame_size="8k")
    with pytest.raises(SystemExit) as exit_:
        main(["bench", "fit", "--suite", "--frame-size", "8k"])
    assert exit_.value.code == 2
    assert "--frame-size: invalid choice: '8k'" in capsys.readouterr().err


def test_masks_table_shows_each_seed_beside_the_click():
    from dolphinfit.app.commands.bench import format_masks

    def scores(iou, error=""):
        return {"mean_iou": iou, "min_iou": iou, "flukes_iou": 0.5, "rostrum_iou": 0.6,
                "seconds_per_frame": 1.0, "outline_offset_px": -0.25, "error": error,
                "seed_seconds": 2.5, "seconds_per_tracked_frame": 0.75}

    clip = {"clip": "grey_green", "backend": "network", "frames": 8, **scores(0.9),
            "seeds": {"auto": scores(0.0, "no animal"), "box": scores(0.88)}}
    summary = {**scores(0.9), "worst_clip_iou": 0.9, "mean_abs_outline_offset_px": 0.25,
               "worst_outline_offset_px": 0.25,
               "seeds": {"auto": {**scores(0.0), "worst_clip_iou": 0.0},
                         "box": {**scores(0.88), "worst_clip_iou": 0.88}}}
    table = format_masks({"clips": [clip], "summary": {"network": summary}})
    header, row, _, total = table.splitlines()
    assert "auto: IoU" in header and "box: IoU" in header
    assert "0.000 0.500 0.600" in row and "0.880 0.500 0.600" in row and "(no animal)" in row
    assert "outline px" in header and " -0.25 " in row and "outline offset 0.25 px" in total
    assert "seed s then" in header and "1.00    2.50  0.75" in row
    assert "1.00 s per frame (the seed 2.50 s, then 0.75 s per frame tracked)" in total
    assert total.endswith("; auto: 0.000 (worst clip 0.000); box: 0.880 (worst clip 0.880)")


def test_bench_masks_defaults_to_the_back_ends_that_always_work():
    """SAM-2 is never in the default list: the bench must not fail where it is not installed."""

    assert build_parser("bench").parse_args(["bench", "masks"]).backends == \
        "network,network-as-drawn,network-colour-edges,colour"


@pytest.mark.parametrize("args, problem", [
    (["--backends", "network,sam2"], "the sam2 back-end needs --sam2-checkpoint PATH"),
    (["--backends", "sam2", "--sam2-checkpoint", "{tmp}/sam2.1_hiera_tiny.txt"],
     "--sam2-checkpoint {tmp}/sam2.1_hiera_tiny.txt: not a SAM-2 checkpoint"),
    (["--sam2-checkpoint", "{tmp}/sam2.1_hiera_tiny.pt"],
     "--sam2-checkpoint {tmp}/sam2.1_hiera_tiny.pt: only used by the sam2 back-end"),
], ids=["no-checkpoint", "not-pt", "without-sam2"])
def test_bench_masks_checks_the_sam2_checkpoint_before_any_work(tmp_path, capsys, args,
                                                                problem):
    (tmp_path / "sam2.1_hiera_tiny.txt").write_text("not a checkpoint")
    (tmp_path / "sam2.1_hiera_tiny.pt").write_bytes(b"")
    assert main(["bench", "masks", *[a.format(tmp=tmp_path) for a in args]]) == 2
    assert problem.format(tmp=tmp_path) in capsys.readouterr().err


def test_the_splits_are_chosen_by_name_and_kept_apart(capsys):
    from dolphinfit.app.commands.bench import _chosen_clips
    from dolphinfit.core.bench.suites import scenarios

    args = build_parser("bench").parse_args(["bench", "fit", "--suite", "--clips", "2"])
    chosen = _chosen_clips(args)
    assert list(chosen) == ["tuning", "held-out", "vtk"]
    assert [s.name for s in chosen["vtk"]] == [s.name for s in scenarios(split="vtk")[:2]]
    assert {s.renderer for s in chosen["vtk"]} == {"vtk"}
    with pytest.raises(InputError, match="suite split: one of tuning, held-out, vtk"):
        scenarios(split="test")
    assert main(["bench", "masks", "--splits", "tuning,test"]) == 2
    assert "--splits: one of tuning, held-out, vtk, got 'test'" in capsys.readouterr().err


def test_the_click_bench_clicks_the_middle_frame_and_prints_its_waits(capsys):
    """The click lands on the target in the visible frame nearest the clip's middle; the
    table gives both waits beside their aims; an unknown part is refused before any work."""
    from dolphinfit.app.commands.bench import format_app
    from dolphinfit.core.bench.click_bench import AIMS_S, middle_click

    truth = {"frames": [{"frame": t, "visible": t not in (4, 5), "seed_px": [10.0 + t, 20.0]}
                        for t in range(10)]}
    seed = middle_click(truth)  # 4 and 5 hidden: 6 lies nearer the middle (5.0) than 3
    assert (seed.x_px, seed.y_px, seed.frame_idx) == (16.0, 20.0, 6)
    with pytest.raises(ValueError, match="never visible"):
        middle_click({"frames": [{"frame": 0, "visible": False}]})
    click = {"backend": "network", "video_s": 10.0, "clip_fps": 25.0, "width_px": 1920,
             "height_px": 1080, "clicked_frame": 125, "fit_frames": 51, "first_mask_s": 2.4,
             "fit_masks_s": 61.0, "mean_iou": 0.93, "worst_iou": 0.88, "aims_s": AIMS_S}
    scan = {"seconds": 8.5, "video_s": 10.0, "seconds_per_video_minute": 51.0, "samples": 10,
            "animals": 1}
    text = format_app({"click": click, "scan": scan})
    assert "its mask after 2.4 s (aim ≤ 3)" in text
    assert "the fit's 51 frames after 61.0 s (aim ≤ 15)" in text
    assert "the scan: 10 s of 1080p in 8.5 s, 51 s per minute of video (aim ≤ 30)" in text
    assert main(["bench", "app", "--parts", "clicks"]) == 2
    assert "--parts" in capsys.readouterr().err
