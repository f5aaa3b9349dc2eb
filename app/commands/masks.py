"""Track the dolphin through a clip (or find it in a still) and write its masks.

  dolphinfit masks CLIP|IMAGE|FOLDER (--seed X,Y | --box X,Y,W,H | --auto) --out DIR [--frame N]
                   [--backend network|network-colour-edges|colour|sam2
                    [--sam2-checkpoint PATH]] [--every K|fit] [--device auto|cpu|cuda]

--backend picks who draws the masks: the salient-object network on a crop around the animal,
its outline drawn by the project's edge network (default; keeps light-grey flukes over green
water; about 0.4 s per 1080p frame on two cores), the same with the outline placed by colour
(network-colour-edges, the default before the edge network), the colour tracker (fast, for
dark animals over clear water) or SAM-2, the paper's segmenter, for users who installed its
`sam2` package themselves: --sam2-checkpoint names the checkpoint file downloaded for it (e.g.
sam2.1_hiera_tiny.pt); it needs --seed or --box. --every K runs the network or SAM-2 on every
K-th frame only (the others are written empty); --every fit on the frames a `dolphinfit fit`
with its default rate and frame cap takes. --device is
where the edge network and SAM-2 run: auto (the default) takes a CUDA GPU when the installed
torch sees one, else the CPU; the salient network and the colour tracker always run on the
CPU.

--seed is a click on the animal and --box a box around it (top-left x, y, width, height), in
pixels of frame N (--frame, default 0); --auto finds the animal by itself in frame N or,
where none shows there, in frames spread over the clip (the network's most salient lone
animal of a dolphin's length and shape, else the colour detector's darkest elongated
blob). The tracker runs forwards and backwards from that
frame and marks frames where the animal is lost (dived out of sight). --out DIR writes
DIR/%06d.png, one per frame (255 = dolphin, empty where lost); a path ending in .npz writes
one .npz file instead. Masks from another segmenter (a SAM-family model run elsewhere, say)
are used by writing them in one of these formats.
"""

import argparse
import sys
from collections.abc import Collection, Sequence
from pathlib import Path

from dolphinfit.app.commands.device_option import add_device_argument, chosen_device
from dolphinfit.app.progress import is_tenth
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.io.frame_source import Clip
from dolphinfit.core.io.masks import MaskTrack, check_mask_output, write_masks
from dolphinfit.core.io.report import format_runs
from dolphinfit.core.io.media import open_media
from dolphinfit.core.limits import count, number, positive
from dolphinfit.core.progress import Progress
from dolphinfit.core.segment.backends import BACKENDS, DEFAULT_BACKEND, SAM2, make_segmenter
from dolphinfit.core.segment.sam2_backend import check_checkpoint
from dolphinfit.core.segment.segmenter import AutoSeed, BoxSeed, PointSeed, Seed
from dolphinfit.core.segment.tracking_loop import check_seed_inside



def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The clip, one kind of seed, the seed frame and the output."""
    parser.add_argument("clip", type=Path, help="the video, a still image or a folder of frames")
    seed = parser.add_mutually_exclusive_group(required=True)
    seed.add_argument("--seed", metavar="X,Y", help="a click on the animal, pixels")
    seed.add_argument("--box", metavar="X,Y,W,H", help="a box around the animal, pixels")
    seed.add_argument("--auto", action="store_true", help="find the animal automatically")
    parser.add_argument("--frame", type=int, default=0, metavar="N",
                        help="the frame the seed is in (default 0)")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR",
                        help="folder for %%06d.png masks, or a .npz file")
    parser.add_argument("--backend", choices=tuple(BACKENDS), default=DEFAULT_BACKEND,
                        help=f"who draws the masks (default {DEFAULT_BACKEND})")
    add_sam2_argument(parser)
    parser.add_argument("--every", default="1", metavar="K|fit",
                        help="network and SAM-2: segment every K-th frame only (default 1), or "
                             "'fit': the frames a default `dolphinfit fit` takes")
    add_device_argument(parser, "where the edge network and SAM-2 run (the salient network "
                                "and the colour tracker run on the CPU)")


def add_sam2_argument(parser: argparse.ArgumentParser) -> None:
    """--sam2-checkpoint, for the sam2 back-end."""
    parser.add_argument("--sam2-checkpoint", type=Path, metavar="PATH",
                        help="the SAM-2 checkpoint (.pt) for the sam2 back-end, downloaded by you")


def sam2_checkpoint(args: argparse.Namespace, backends: Collection[str]) -> Path | None:
    """--sam2-checkpoint checked at the boundary: an existing .pt file when ``backends``
    include sam2, absent otherwise; InputError naming the option."""
    path = args.sam2_checkpoint
    if SAM2 not in backends:
        if path is not None:
            raise InputError(f"--sam2-checkpoint {path}: only used by the {SAM2} back-end")
        return None
    if path is None:
        raise InputError(f"the {SAM2} back-end needs --sam2-checkpoint PATH, a SAM-2 "
                         "checkpoint (.pt) you downloaded")
    try:
        return check_checkpoint(path)
    except InputError as exc:
        raise InputError(f"--sam2-checkpoint {exc}") from None


def _numbers(option: str, text: str, count: int) -> list[float]:
    """``count`` comma-separated numbers; InputError naming the option otherwise."""
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != count:
        raise InputError(f"{option} {text!r}: expected {count} comma-separated numbers")
    return [number(v, f"{option} {text!r}") for v in values]


def parse_seed(args: argparse.Namespace) -> Seed:
    """The seed named on the command line."""
    if args.seed is not None:
        x_px, y_px = _numbers("--seed", args.seed, 2)
        return PointSeed(x_px, y_px, args.frame)
    if args.box is not None:
        x_px, y_px, width_px, height_px = (round(v) for v in _numbers("--box", args.box, 4))
        positive(width_px, f"--box {args.box!r}: width")
        positive(height_px, f"--box {args.box!r}: height")
        return BoxSeed(x_px, y_px, width_px, height_px, args.frame)
    return AutoSeed(args.frame)


def _progress(progress: Progress) -> None:
    """A line on stderr at every tenth of the clip."""
    if is_tenth(progress):
        print(f"tracking: {progress.step}/{progress.total} frames", file=sys.stderr)


def summary(track: MaskTrack, out: Path) -> str:
    """"wrote OUT: T frames, V with the animal; lost in frames …"."""
    lost = ~track.is_visible
    count = track.num_frames
    text = (f"wrote {out}: {count} frame{'s' if count != 1 else ''}, "
            f"{int(track.is_visible.sum())} with the animal")
    return text + (f"; lost in frames {format_runs(lost)}" if lost.any() else "")


def segmented_frames(every: str, clip: Clip) -> Sequence[int]:
    """The frames ``--every`` names: every K-th, or those a default fit takes ("fit");
    InputError naming the option otherwise."""
    if every == "fit":
        return FitConfig().frames_of(clip).tolist()
    try:
        step = int(every)
    except ValueError:
        raise InputError(f"--every {every!r}: expected a whole number of frames, at least 1, "
                         "or 'fit'") from None
    return range(0, clip.num_frames, count(step, 1, "--every"))


def run(args: argparse.Namespace) -> int:
    """Track from the seed and write the masks."""
    check_mask_output(args.out)
    seed = parse_seed(args)
    checkpoint = sam2_checkpoint(args, (args.backend,))
    device = chosen_device(args)
    with open_media(args.clip) as frames:  # a video, a still or a folder of frames
        clip = frames.clip
        if not 0 <= args.frame < clip.num_frames:
            raise InputError(f"--frame {args.frame}: {clip.path} has frames "
                             f"0…{clip.num_frames - 1}")
        try:
            check_seed_inside(seed, clip.width_px, clip.height_px)
        except InputError as exc:
            raise InputError(f"{'--seed' if args.seed is not None else '--box'}: "
                             f"{exc}") from None
        segmenter = make_segmenter(args.backend, segmented_frames(args.every, clip), checkpoint,
                                   device)
        try:
            track = segmenter.segment(frames, seed, progress=_progress)
        except InputError as exc:
            raise InputError(f"{clip.path}: {exc}") from None
    write_masks(track, args.out)
    print(summary(track, args.out))
    return 0
