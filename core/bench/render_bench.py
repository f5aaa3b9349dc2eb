"""``dolphinfit bench render``: the renderer's speed, measured side by side.

Scenes are the template swimming (motion of core/synth) under the paper's camera at 20 m:

- the paper's setting: a full 720×480 frame, forward and backward of a fit-like loss
  (1 − soft IoU + mean squared colour), per frame;
- ROI crops typical of 1920×1080 footage at 20 m (1.46 cm/px): a batch of 256×256 windows
  around the animal, per frame;
- the dense brute-force reference (core/render/dense.py) against the sparse renderer on the
  same scene at the largest image size whose dense pair tensors fit the memory budget;
- a forward-only OpenCV fill of the same front-facing triangles as the floor;
- peak memory of a 64-frame ROI batch, forward and backward, in a fresh process.
"""

import math
import os
import platform
import time
from dataclasses import asdict, dataclass

import cv2
import numpy as np
import torch

from dolphinfit.core.bench.timing import median_ms, median_phases_ms, peak_rss_mb_of
from dolphinfit.core.camera import NadirCamera
from dolphinfit.core.fit.losses import soft_iou_loss
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.template import load_template
from dolphinfit.core.render.dense import dense_render
from dolphinfit.core.render.rasterize import cross2
from dolphinfit.core.render.render import Appearance, project_to_viewport, render
from dolphinfit.core.render.settings import RasterSettings, Viewport
from dolphinfit.core.render.shade import SGLight
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.motion import swim

ALTITUDE_M = 20.0
LENGTH_M = 2.5
PAPER_SIZE = (720, 480)
FOOTAGE_SIZE = (1920, 1080)
ROI_PX = 256
ROI_BATCH = 16
MEMORY_BATCH = 64
DENSE_SIZES = ((160, 120), (128, 96), (96, 72), (64, 48), (48, 36))
QUICK_DENSE_SIZE = (24, 18)     # the smoke test's: the dense reference costs pixels × faces²
# Peak memory of dense_render forward+backward per (pixel, face) pair, float32: measured
# 241–247 B at 48×36 to 96×72 px with the 8000-face template.
DENSE_BYTES_PER_PAIR = 250
DENSE_MEMORY_FRACTION = 0.3     # of physical memory the dense reference may use
# The dense reference's contour search grows with faces², so the dense comparison (both sides)
# and the second ROI figure use DIB-R's own soft mask over faces.
FACES_SETTINGS = RasterSettings(soft_primitives="faces")


@dataclass(frozen=True)
class RenderBench:
    """Figures of one run (milliseconds per frame unless named otherwise)."""

    threads: int
    faces: int
    paper_forward_ms: float
    paper_backward_ms: float
    paper_ms: float
    paper_covered_px: int
    paper_floor_ms: float
    ratio_vs_floor: float
    roi_forward_ms: float
    roi_backward_ms: float
    roi_ms: float
    roi_floor_ms: float
    roi_ratio_vs_floor: float
    roi_faces_ms: float           # the same batch with the "faces" soft mask (DIB-R's)
    roi_faces_ratio_vs_floor: float
    dense_size_px: tuple[int, int]
    dense_ms: float
    sparse_ms_at_dense_size: float
    speedup_vs_dense: float
    memory_frames: int
    peak_memory_mb: float
    torch_version: str
    cpu: str


def _model_and_appearance() -> tuple[DolphinModel, Appearance]:
    template = load_template()
    model = DolphinModel(template)
    appearance = Appearance(
        albedo=torch.tensor(template.albedo / 255.0, dtype=torch.float32),
        face_uvs=torch.tensor(template.uvs[template.face_uvs_idx], dtype=torch.float32),
        light=SGLight.overhead_sun(), f_water=torch.tensor([0.5, 0.15, 0.1]))
    return model, appearance


def swimming_verts(model: DolphinModel, num_frames: int) -> torch.Tensor:
    """(T, V, 3) the template at 2.5 m swimming at the surface (synth motion, fixed seed)."""
    config = SynthConfig(fps=25.0, duration_s=num_frames / 25.0, dive_depth_m=0.0,
                         heading_deg=25.0)
    motion = swim(config, model.group_names, np.random.default_rng(0))
    betas = model.zero_params(1)[0]
    betas[:, 0] = math.log(LENGTH_M / load_template().length_m)
    with torch.no_grad():
        return model(betas, torch.as_tensor(motion.pose_aa, dtype=torch.float32),
                     torch.as_tensor(motion.transl, dtype=torch.float32)).verts


def _camera(size: tuple[int, int], num_frames: int, altitude_m: float = ALTITUDE_M):
    intrinsics = CameraIntrinsics.from_sensor(12.29, 17.27, *size)
    return intrinsics, NadirCamera(intrinsics, torch.full((num_frames,), altitude_m))


def _roi_viewport(camera: NadirCamera, verts: torch.Tensor) -> Viewport:
    centre = camera.project(verts.mean(1, keepdim=True))[:, 0]
    corner = (centre - ROI_PX / 2).round().to(torch.int64)
    return Viewport(corner[:, 0], corner[:, 1], ROI_PX, ROI_PX)


def _sparse_renderer(settings: RasterSettings = RasterSettings()):
    def run(verts, faces, appearance, camera, viewport):
        out = render(verts, faces, appearance, camera, viewport, settings)
        return out.soft_mask, out.rgb
    return run


def _forward_backward(verts, faces, appearance, camera, viewport, renderer=_sparse_renderer()):
    """A closure running forward and backward of a fit-like loss; returns the seconds of each.

    ``renderer`` returns (soft mask, colour) of meshes (T, V, 3).
    """
    def forward():
        return renderer(verts.detach().requires_grad_(), faces, appearance, camera, viewport)

    target = forward()[0].detach()

    def step() -> tuple[float, float]:
        start = time.perf_counter()
        soft, rgb = forward()
        middle = time.perf_counter()
        (soft_iou_loss(soft, target) + (rgb ** 2).mean()).backward()
        return middle - start, time.perf_counter() - middle

    return step


def opencv_floor_ms(verts: torch.Tensor, faces: torch.Tensor, camera: NadirCamera,
                    viewport: Viewport, repeats: int) -> float:
    """Forward-only OpenCV fill of the front-facing triangles of every frame, per frame."""
    xy, _ = project_to_viewport(verts, camera, viewport)
    tri = xy[:, faces].numpy()
    front = cross2(torch.as_tensor(tri[..., 1, :] - tri[..., 0, :]),
                   torch.as_tensor(tri[..., 2, :] - tri[..., 0, :])).numpy() < 0
    polygons = [list(np.round(tri[t][front[t]] * 16).astype(np.int32))
                for t in range(len(tri))]
    image = np.zeros((viewport.height_px, viewport.width_px), np.uint8)

    def fill():
        for frame_polygons in polygons:
            image[:] = 0
            cv2.fillPoly(image, frame_polygons, 255, lineType=cv2.LINE_8, shift=4)

    return median_ms(fill, repeats) / len(polygons)


def dense_size(num_faces: int) -> tuple[int, int]:
    """The largest candidate size whose dense pair tensors fit the memory budget."""
    budget = DENSE_MEMORY_FRACTION * os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    for width, height in DENSE_SIZES:
        if width * height * num_faces * DENSE_BYTES_PER_PAIR <= budget:
            return width, height
    return DENSE_SIZES[-1]


def _dense_renderer(settings: RasterSettings):
    def run(verts, faces, appearance, camera, viewport):
        xy, depth = project_to_viewport(verts, camera, viewport)
        _, soft, rgb = dense_render(verts, xy, depth, faces, appearance, viewport.height_px,
                                    viewport.width_px, settings)
        return soft, rgb
    return run


def memory_job(num_frames: int):
    """Set-up for the peak-memory child: returns the forward+backward of a ROI batch."""
    model, appearance = _model_and_appearance()
    verts = swimming_verts(model, num_frames)
    _, camera = _camera(FOOTAGE_SIZE, num_frames)
    return _forward_backward(verts, model.faces, appearance, camera,
                             _roi_viewport(camera, verts))


def bench_render(repeats: int = 5, quick: bool = False) -> RenderBench:
    """Run every measurement once, side by side in this process.

    ``quick`` shrinks batches and the dense size for a smoke test; its figures are not the
    benchmark's.
    """
    roi_batch, memory_batch = (2, 2) if quick else (ROI_BATCH, MEMORY_BATCH)
    model, appearance = _model_and_appearance()
    faces = model.faces

    paper_verts = swimming_verts(model, 1)
    paper_intr, paper_cam = _camera(PAPER_SIZE, 1)
    paper_view = Viewport.full_frame(paper_intr, 1)
    (paper_fwd, paper_bwd), paper_both = median_phases_ms(
        _forward_backward(paper_verts, faces, appearance, paper_cam, paper_view), repeats)
    paper_floor = opencv_floor_ms(paper_verts, faces, paper_cam, paper_view, repeats * 4)
    with torch.no_grad():
        covered = int(render(paper_verts, faces, appearance, paper_cam, paper_view).coverage.sum())

    roi_verts = swimming_verts(model, roi_batch)
    _, roi_cam = _camera(FOOTAGE_SIZE, roi_batch)
    roi_view = _roi_viewport(roi_cam, roi_verts)
    (roi_fwd, roi_bwd), roi_both = median_phases_ms(
        _forward_backward(roi_verts, faces, appearance, roi_cam, roi_view), repeats)
    roi_fwd, roi_bwd, roi_both = roi_fwd / roi_batch, roi_bwd / roi_batch, roi_both / roi_batch
    _, roi_faces = median_phases_ms(_forward_backward(
        roi_verts, faces, appearance, roi_cam, roi_view,
        renderer=_sparse_renderer(FACES_SETTINGS)), repeats)
    roi_faces /= roi_batch
    roi_floor = opencv_floor_ms(roi_verts, faces, roi_cam, roi_view, repeats * 4)

    size = QUICK_DENSE_SIZE if quick else dense_size(faces.shape[0])
    # altitude at which the 2.5 m animal spans about 80 % of the dense image's width
    focal_px = 12.29 / 17.27 * size[0]
    dense_intr, dense_cam = _camera(size, 1, altitude_m=focal_px * LENGTH_M / (0.8 * size[0]))
    dense_view = Viewport.full_frame(dense_intr, 1)
    _, sparse_ms = median_phases_ms(_forward_backward(
        paper_verts, faces, appearance, dense_cam, dense_view,
        renderer=_sparse_renderer(FACES_SETTINGS)), repeats)
    _, dense_ms = median_phases_ms(_forward_backward(
        paper_verts, faces, appearance, dense_cam, dense_view,
        renderer=_dense_renderer(FACES_SETTINGS)), max(1, repeats // 2))

    return RenderBench(
        threads=torch.get_num_threads(), faces=int(faces.shape[0]),
        paper_forward_ms=paper_fwd, paper_backward_ms=paper_bwd,
        paper_ms=paper_both, paper_covered_px=covered, paper_floor_ms=paper_floor,
        ratio_vs_floor=paper_both / paper_floor,
        roi_forward_ms=roi_fwd, roi_backward_ms=roi_bwd, roi_ms=roi_both,
        roi_floor_ms=roi_floor, roi_ratio_vs_floor=roi_both / roi_floor,
        roi_faces_ms=roi_faces, roi_faces_ratio_vs_floor=roi_faces / roi_floor,
        dense_size_px=size, dense_ms=dense_ms, sparse_ms_at_dense_size=sparse_ms,
        speedup_vs_dense=dense_ms / sparse_ms,
        memory_frames=memory_batch,
        peak_memory_mb=peak_rss_mb_of(__name__, "memory_job", memory_batch),
        torch_version=torch.__version__, cpu=platform.processor() or platform.machine(),
    )


def bench_to_json(result: RenderBench) -> dict:
    """JSON-ready dict of a run."""
    return asdict(result)
