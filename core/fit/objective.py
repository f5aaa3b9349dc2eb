"""What a fit minimises: the data, model and fixed inputs it evaluates its parameters against,
the loss of one step (silhouette, colour and pyramid terms per chunk of frames, priors on
the whole clip) and its gradients, rendered in chunks on worker threads."""

import math
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, wait
from functools import reduce

import numpy as np
import torch

from dolphinfit.core.fit import losses
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.data import FitData
from dolphinfit.core.fit.reporter import FitReporter
from dolphinfit.core.fit.scene import SceneParams
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.model.lbs import axis_angle_to_matrix
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.template import Template
from dolphinfit.core.progress import Cancelled, check_cancel
from dolphinfit.core.render.contour import mesh_edges
from dolphinfit.core.render.pyramid import pyramid_loss, silhouette_pyramid
from dolphinfit.core.render.render import Appearance, RenderOutput, render
from dolphinfit.core.render.settings import RasterSettings, Viewport

V_SURF_M_S = 6.6      # the paper's upward nudge while pointing up
V_DIVE_M_S = 2.2      # the paper's downward nudge while pointing down
SMOOTH_REFERENCE_S = 1.0 / 25.0   # frame interval the smoothness weights refer to
WAIT_S = 0.2          # how often the fit's thread checks cancel while workers render


class FitProblem:
    """The data, model and fixed inputs one fit evaluates its parameters against; chunks of
    frames are rendered in ``pool``'s threads where there is one."""

    def __init__(self, data: FitData, model: DolphinModel, template: Template,
                 config: FitConfig, reporter: FitReporter, cancel: threading.Event | None,
                 pool: Executor | None = None, chunk_frames: int | None = None):
        self.data, self.model, self.config = data, model, config
        self.reporter, self.cancel, self.pool = reporter, cancel, pool
        self.chunk_frames = chunk_frames or config.frames_per_chunk
        self.template = template
        self.settings = RasterSettings(max_faces_per_pixel=config.max_faces_per_pixel,
                                       soft_primitives=config.soft_primitives)
        self.edges = mesh_edges(model.faces)
        like = dict(dtype=torch.float32, device=data.device)
        self.face_uvs = torch.tensor(template.uvs[template.face_uvs_idx], **like)
        self.time_s = torch.as_tensor(data.time_s, **like)
        interval = float(np.median(np.diff(data.time_s))) if data.num_frames > 1 else 1.0
        self.frame_ratio = SMOOTH_REFERENCE_S / interval
        self.set_targets(data.masks)
        self.use_all_frames()

    def set_targets(self, targets: torch.Tensor) -> None:
        """Fit to soft ``targets`` (T, H, W); their pyramid is computed once here."""
        self.targets = targets
        with torch.no_grad():
            self.target_pyramid = silhouette_pyramid(targets)

    def use_all_frames(self) -> None:
        """Render every frame in each step."""
        self.set_frames(self.data.every_frame())

    def set_frames(self, frames: torch.Tensor) -> None:
        """Render only ``frames`` in each step, in chunks."""
        self.frames = frames
        self.chunks = equal_chunks(frames, self.chunk_frames)
        self.num_used = len(frames)

    def map_chunks(self, work: Callable[[object], object], chunks: Sequence,
                   cancellable: bool = True) -> list:
        """``work(chunk)`` for each chunk, in order, in the pool's threads where there is
        one; between chunks the heartbeat is kept and, if ``cancellable``, the cancel
        request honoured."""
        cancel = self.cancel if cancellable else None
        if self.pool is None:
            results = []
            for chunk in chunks:
                check_cancel(cancel)
                self.reporter.heartbeat()
                results.append(work(chunk))
            return results
        check_cancel(cancel)
        futures = [self.pool.submit(work, chunk) for chunk in chunks]
        try:
            while wait(futures, timeout=WAIT_S).not_done:
                check_cancel(cancel)
                self.reporter.heartbeat()
        except Cancelled:
            for future in futures:
                future.cancel()
            wait(futures)
            raise
        return [future.result() for future in futures]

    def frame_ious(self, params: SceneParams) -> torch.Tensor:
        """(T,) hard IoU of every frame at ``params``."""
        def work(chunk: torch.Tensor) -> torch.Tensor:
            with torch.no_grad():   # grad mode is per thread
                return mask_iou(self.render_chunk(params, chunk).coverage,
                                self.data.masks[chunk] > 0.5)

        chunks = equal_chunks(self.data.every_frame(), self.chunk_frames)
        return torch.cat(self.map_chunks(work, chunks, cancellable=False))

    def restrict_to_explained_frames(self, params: SceneParams) -> list[str]:
        """Keep for the shape stage the frames the pose stages explain (config doc)."""
        iou = self.frame_ious(params)
        keep = iou >= float(iou.median()) - self.config.shape_iou_margin
        self.set_frames(torch.nonzero(keep)[:, 0])
        dropped = self.data.frame_idx[(~keep).cpu().numpy()]
        if len(dropped) == 0:
            return []
        return [f"{len(dropped)} of {len(iou)} frames left out of the shape stage (IoU after "
                f"the pose stages below the median {float(iou.median()):.3f} − "
                f"{self.config.shape_iou_margin}): frames {', '.join(map(str, dropped[:8]))}"
                + (" …" if len(dropped) > 8 else "")]

    def profile(self, params: SceneParams) -> torch.Tensor | None:
        """The profile field's coefficients, None when the configuration has no field."""
        return params.profile if self.config.profile_field else None

    def posed_verts(self, params: SceneParams, frames: torch.Tensor) -> torch.Tensor:
        """(len(frames), V, 3) posed meshes of ``frames`` at ``params``."""
        return self.model(params.full_betas(), params.pose()[frames],
                          params.transl[frames], self.profile(params)).verts

    def render_chunk(self, params: SceneParams, chunk: torch.Tensor) -> RenderOutput:
        """The silhouettes of frames ``chunk`` at ``params``, unshaded."""
        return self.render_verts(params, chunk, self.posed_verts(params, chunk), shade=False)

    def render_verts(self, params: SceneParams, chunk: torch.Tensor,
                     verts: torch.Tensor, shade: bool = True) -> RenderOutput:
        """Render the posed meshes ``verts`` (len(chunk), V, 3) of frames ``chunk``."""
        appearance = Appearance(params.albedo, self.face_uvs, params.light(), params.f_water)
        viewport = Viewport(self.data.viewport.x0_px[chunk], self.data.viewport.y0_px[chunk],
                            self.data.viewport.width_px, self.data.viewport.height_px)
        return render(verts, self.model.faces, appearance, self.data.camera.select(chunk),
                      viewport, self.settings, self.edges, shade)

    def step_loss(self, params: SceneParams, pyramid_weight: float,
                  leaves: list[torch.Tensor], colour: bool, colour_geometry: bool
                  ) -> tuple[dict, torch.Tensor]:
        """Set the gradients of ``leaves`` (the parameters being optimised: autograd skips
        what only the others need) to those of the total loss, with the colour term only
        with ``colour`` and its gradient on the geometry only with ``colour_geometry``;
        returns term values and per-frame IoU.

        The model poses every frame of the step at once, here; the chunks render their
        frames' meshes as their own leaves and return the gradients of the loss for them,
        which go back through the model once. Gradients are summed in chunk order.
        """
        posed = self.posed_verts(params, self.frames)
        meshes = posed.detach().split([len(chunk) for chunk in self.chunks])
        chunks = self.map_chunks(
            lambda item: self.chunk_loss(params, *item, pyramid_weight, leaves, colour,
                                         colour_geometry),
            list(zip(self.chunks, meshes)))
        weights = self.config.weights
        prior_terms = self.prior_terms(params)
        prior_total = sum(getattr(weights, name) * value for name, value in prior_terms.items())
        grads = [*(grads for _, _, grads, _ in chunks),
                 torch.autograd.grad(posed, leaves, torch.cat([g for _, g, _, _ in chunks]),
                                     materialize_grads=True),
                 torch.autograd.grad(prior_total, leaves, materialize_grads=True)]
        for leaf, parts in zip(leaves, zip(*grads)):
            leaf.grad = reduce(torch.add, parts)
        terms = {name: sum(chunk_terms[name] for chunk_terms, _, _, _ in chunks)
                 for name in chunks[0][0]}
        terms.update({name: float(value.detach()) for name, value in prior_terms.items()})
        terms["total"] += float(prior_total.detach())
        return terms, torch.cat([iou for _, _, _, iou in chunks])

    def chunk_loss(self, params: SceneParams, chunk: torch.Tensor, verts: torch.Tensor,
                   pyramid_weight: float, leaves: list[torch.Tensor], colour: bool,
                   colour_geometry: bool
                   ) -> tuple[dict[str, float], torch.Tensor, tuple[torch.Tensor, ...],
                              torch.Tensor]:
        """One chunk's loss terms (the colour term, "rgb", only with ``colour``), the
        gradients of its total for its posed meshes ``verts`` (detached; without the colour
        term's unless ``colour_geometry``) and for ``leaves``, and its frames' IoU
        (thread-safe: it changes nothing shared)."""
        weights = self.config.weights
        num_frames = self.num_used
        verts = verts.requires_grad_()
        out = self.render_verts(params, chunk, verts, shade=colour)
        mask_term = losses.soft_iou_loss(out.soft_mask, self.targets[chunk]) / num_frames
        terms = {"mask": float(mask_term.detach()), "pyramid": 0.0}
        total = weights.mask * mask_term
        if colour:
            rgb_term = self.rgb_term(out, chunk) / num_frames
            total = total + weights.rgb * rgb_term
            terms["rgb"] = float(rgb_term.detach())
        if pyramid_weight > 0:
            pyramid_term = (pyramid_loss(out.soft_mask, [level[chunk] for level in
                                                         self.target_pyramid])
                            * len(chunk) / num_frames)
            total = total + pyramid_weight * pyramid_term
            terms["pyramid"] = float(pyramid_term.detach())
        terms["total"] = float(total.detach())
        if colour_geometry or not colour:
            vert_grad, *grads = torch.autograd.grad(total, [verts, *leaves],
                                                    materialize_grads=True)
        else:   # the meshes are the only way to the geometry: the colour term skips them
            colour = weights.rgb * rgb_term
            vert_grad, *grads = torch.autograd.grad(total - colour, [verts, *leaves],
                                                    retain_graph=True, materialize_grads=True)
            grads = map(torch.add, grads,
                        torch.autograd.grad(colour, leaves, materialize_grads=True))
        return terms, vert_grad, tuple(grads), mask_iou(out.coverage,
                                                       self.data.masks[chunk] > 0.5)

    def rgb_term(self, out: RenderOutput, chunk: torch.Tensor) -> torch.Tensor:
        """The colour loss of a chunk's render, read at its covered pixels only."""
        pixels = self.data.viewport.num_pixels
        local_frame = torch.div(out.pixel, pixels, rounding_mode="floor")
        at = chunk[local_frame] * pixels + out.pixel % pixels
        return losses.rgb_loss(out.pixel_rgb, local_frame,
                               self.data.images.reshape(-1, 3)[at],
                               self.data.masks.reshape(-1)[at], len(chunk))

    def prior_terms(self, params: SceneParams) -> dict[str, torch.Tensor]:
        order = self.config.smooth_order
        ratio = self.frame_ratio
        rotations = axis_angle_to_matrix(params.root_aa)
        terms = {
            "pose": losses.pose_prior(params.body_pose),
            "pitch_bend": losses.pitch_bend_prior(params.body_pose, ~self.model.fin_groups[1:]),
            "scale": losses.scale_prior(params.betas),
            "scale_axes": losses.scale_axes_prior(params.betas),
            "scale_smooth": losses.scale_smooth_prior(params.betas, self.model.group_parents),
            "smooth_pos": losses.smoothness(params.transl, order, ratio),
            "smooth_rot": losses.rotation_smoothness(rotations, order, ratio),
            "smooth_pose": losses.smoothness(params.body_pose, order, ratio),
            "depth": losses.depth_prior(params.transl, self.config.init_depth_m),
            "glide": losses.glide_prior(params.transl, rotations[:, :, 0], self.time_s),
        }
        if self.config.profile_field:
            terms["profile"] = losses.profile_prior(params.profile)
            terms["profile_smooth"] = losses.profile_smoothness(params.profile)
        if self.config.use_vertical_prior:
            terms["vertical"] = losses.vertical_motion(params.transl, rotations[:, 2, 0],
                                                       self.time_s, V_SURF_M_S, V_DIVE_M_S)
        if self.config.use_direction_loss:
            terms["direction"] = losses.direction_loss(rotations[:, :2, 0], params.transl)
        return terms


def equal_chunks(frames: torch.Tensor, max_size: int) -> list[torch.Tensor]:
    """``frames`` in consecutive chunks of at most ``max_size`` frames, of sizes that differ
    by one at most: the fewest such chunks, rounded up to an even number (where there are
    frames enough), so that two workers share any step evenly. The rule does not depend on
    the number of workers, so neither do the results."""
    count = math.ceil(len(frames) / max_size)
    count = max(1, min(len(frames), count + count % 2))
    return list(torch.tensor_split(frames, count))


def evenly_spaced(frames: torch.Tensor, limit: int) -> torch.Tensor:
    """At most ``limit`` of ``frames`` (all of them for 0), spread evenly from first to last."""
    if limit <= 0 or len(frames) <= limit:
        return frames
    picks = torch.linspace(0, len(frames) - 1, limit, device=frames.device)
    return frames[picks.round().to(torch.int64)]
