"""Procedural builder of the dolphin template (run once by ``dolphinfit template build``).

Assembles the body tube (``body.py``), the fins extruded from it (``fins.py``), the skeleton
and skinning weights (``skeleton.py``), and the UV atlas and albedo (``texture.py``) into a
:class:`~core.model.template.Template`. Deterministic: no random numbers, fixed ordering.
"""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.measure.stations import STATION_FRACTIONS
from dolphinfit.core.model.body import (
    RING_SIZE, VENTRAL, BodyTube, body_faces, build_body, mirrored_quad, ring_angles_deg,
)
from dolphinfit.core.model.fins import (
    DORSAL_FIN, FLIPPER, FLUKE, FinSpec, fin_frame, layer_positions, strip_faces,
)
from dolphinfit.core.model.profile import ring_fractions, station_rows
from dolphinfit.core.model.skeleton import (
    JOINTS, ROOT_T, fin_weights, group_names, joint_index, spine_weights,
)
from dolphinfit.core.model.template import Template
from dolphinfit.core.model.texture import body_uv, build_albedo, fin_uv

TEMPLATE_LENGTH_M = 2.6  # rostrum tip to fluke notch: the paper's average T. aduncus length


@dataclass(frozen=True)
class Strip:
    """One fin to grow: its joint, planform, side, and the body quad slot it replaces."""

    joint: str
    spec: FinSpec
    mirror: bool
    quad_slot: int


STRIPS = (
    Strip("dorsal_fin", DORSAL_FIN, False, RING_SIZE - 1),
    Strip("flipper_l", FLIPPER, False, FLIPPER.attachment.pair_side_idx),
    Strip("flipper_r", FLIPPER, True, mirrored_quad(FLIPPER.attachment.pair_side_idx)),
    Strip("fluke_l", FLUKE, False, FLUKE.attachment.pair_side_idx),
    Strip("fluke_r", FLUKE, True, mirrored_quad(FLUKE.attachment.pair_side_idx)),
)


@dataclass
class GrownFin:
    """A fin added to the mesh: its loops of vertex indices and its faces."""

    loops_a: np.ndarray     # (K + 1, C) int64, base loop first
    loops_b: np.ndarray     # (K + 1, C) int64
    faces: np.ndarray       # (F, 3) int64
    chord_s: np.ndarray     # (C,) chord fraction of each base row


UV_DECIMALS = 9


def build_template(length_m: float = TEMPLATE_LENGTH_M) -> Template:
    """Build the template with body length ``length_m`` (rostrum tip to fluke notch)."""
    rows_t = ring_fractions()
    angles = ring_angles_deg(rows_t, DORSAL_FIN.attachment, FLUKE.attachment)
    tube = build_body(rows_t, angles, length_m, ROOT_T)

    verts = [tube.verts]
    num_verts = len(tube.verts)
    removed: set[tuple[int, int]] = set()
    fins: dict[str, GrownFin] = {}
    for strip in STRIPS:
        rows = _strip_rows(rows_t, strip.spec)
        removed.update((int(row), strip.quad_slot) for row in rows[:-1])
        base_a = tube.ring_vertex(rows, strip.quad_slot)
        base_b = tube.ring_vertex(rows, strip.quad_slot + 1)
        frame = fin_frame(strip.spec, strip.mirror)
        side_a, side_b = layer_positions(strip.spec, frame, tube.verts[base_a],
                                         tube.verts[base_b], length_m)
        num_layers, num_chord = side_a.shape[:2]
        new_a = num_verts + np.arange(num_layers * num_chord).reshape(num_layers, num_chord)
        new_b = new_a + num_layers * num_chord
        num_verts += 2 * num_layers * num_chord
        verts.extend([side_a.reshape(-1, 3), side_b.reshape(-1, 3)])
        loops_a, loops_b = np.vstack([base_a, new_a]), np.vstack([base_b, new_b])
        mid = 0.5 * (tube.verts[base_a] + tube.verts[base_b])
        chord_pos = (mid - mid[0]) @ frame.chord
        fins[strip.joint] = GrownFin(loops_a, loops_b, strip_faces(loops_a, loops_b),
                                     chord_pos / chord_pos[-1])
    verts = np.concatenate(verts)

    tube_faces, tube_slots = body_faces(tube, removed)
    faces = np.concatenate([tube_faces] + [fin.faces for fin in fins.values()])
    corner_uvs = np.concatenate(
        [_body_corner_uvs(tube, tube_faces, tube_slots)]
        + [_fin_corner_uvs(strip, fins[strip.joint]) for strip in STRIPS])
    # corners that share a UV agree only up to float noise, whose last bits differ between
    # numpy builds: merge them on rounded values so the asset rebuilds the same everywhere
    uvs, inverse = np.unique(np.round(corner_uvs.reshape(-1, 2), UV_DECIMALS), axis=0,
                             return_inverse=True)

    rest_joints = _rest_joints(tube, fins, length_m)
    joint_axes = np.stack([
        fin_frame(strip.spec, strip.mirror).as_matrix() if (strip := _strip_of(joint.name))
        else np.eye(3) for joint in JOINTS])
    groups = group_names()
    names = tuple(joint.name for joint in JOINTS)
    return Template(
        verts=verts,
        faces=faces,
        uvs=uvs,
        face_uvs_idx=inverse.reshape(-1, 3).astype(np.int64),
        albedo=build_albedo(),
        skin_weights=_skin_weights(tube, fins, num_verts),
        rest_joints=rest_joints,
        joint_parents=np.array([names.index(j.parent) if j.parent else -1 for j in JOINTS],
                               dtype=np.int64),
        joint_group=np.array([groups.index(j.group) for j in JOINTS], dtype=np.int64),
        joint_mirror=np.array([j.mirror for j in JOINTS], dtype=bool),
        joint_axes=joint_axes,
        station_fractions=STATION_FRACTIONS.copy(),
        station_rings=np.stack([tube.ring_vertex(row, np.arange(RING_SIZE))
                                for row in station_rows(rows_t)]).astype(np.int64),
        joint_names=names,
        group_names=groups,
        rostrum_idx=tube.rostrum_idx,
        notch_idx=tube.notch_idx,
        length_m=float(length_m),
        fin_vertices={j: np.concatenate([f.loops_a[1:].ravel(), f.loops_b[1:].ravel()])
                      for j, f in fins.items()},
        fin_bases={j: np.concatenate([f.loops_a[0], f.loops_b[0]]) for j, f in fins.items()},
    )


def _strip_of(joint: str) -> Strip | None:
    return next((strip for strip in STRIPS if strip.joint == joint), None)


def _strip_rows(rows_t: np.ndarray, spec: FinSpec) -> np.ndarray:
    """Indices of the body rings a fin's base spans (contiguous, at least two)."""
    att = spec.attachment
    rows = np.flatnonzero((rows_t >= att.t_start - 1e-12) & (rows_t <= att.t_end + 1e-12))
    if len(rows) < 2 or np.any(np.diff(rows) != 1):
        raise ValueError(f"{spec.name}: base rows {rows} are not a contiguous run")
    return rows


def _signed_angle(tube: BodyTube, vertex: np.ndarray, slot: np.ndarray) -> np.ndarray:
    """Signed angle of ring vertices in [−180°, 180°], continuous within quad ``slot``."""
    ring_idx = vertex - 1
    phi = tube.angles_deg.reshape(-1)[ring_idx]
    j = ring_idx % RING_SIZE
    return np.where((slot >= VENTRAL) & (j >= VENTRAL), phi - 360.0, phi)


def _body_corner_uvs(tube: BodyTube, faces: np.ndarray, slots: np.ndarray) -> np.ndarray:
    """(F, 3, 2) UVs of the tube's face corners; apex corners take their fan slot's angle."""
    slot = np.broadcast_to(slots[:, None], faces.shape)
    is_apex = (faces == tube.rostrum_idx) | (faces == tube.notch_idx)
    ring_vertex = np.where(is_apex, 1, faces)
    t = tube.rows_t[(ring_vertex - 1) // RING_SIZE]
    phi = _signed_angle(tube, ring_vertex, slot)
    ring_corners = np.where(is_apex, 0.0, phi)
    fan_mid = ring_corners.sum(axis=1, keepdims=True) / 2.0
    phi = np.where(is_apex, fan_mid, phi)
    t = np.where(faces == tube.rostrum_idx, 0.0, np.where(faces == tube.notch_idx, 1.0, t))
    return body_uv(t, phi)


def _fin_corner_uvs(strip: Strip, fin: GrownFin) -> np.ndarray:
    """(F, 3, 2) UVs of a fin's face corners from each vertex's layer, chord row and side."""
    num_layers = fin.loops_a.shape[0] - 1
    span_f = np.arange(num_layers + 1)[:, None] / num_layers
    lookup: dict[int, np.ndarray] = {}
    # Mirroring swaps which side is on top: keep the atlas' upper half on the same face.
    for loops, upper in ((fin.loops_a, not strip.mirror), (fin.loops_b, strip.mirror)):
        uv = fin_uv(strip.spec.name, fin.chord_s[None, :], span_f, upper)
        lookup.update(zip(loops.ravel().tolist(), uv.reshape(-1, 2)))
    return np.array([[lookup[v] for v in face] for face in fin.faces.tolist()])


def _rest_joints(tube: BodyTube, fins: dict[str, GrownFin], length_m: float) -> np.ndarray:
    """(J, 3) spine joints on the body axis; fin joints at the centre of their base."""
    joints = []
    for joint in JOINTS:
        if joint.spine_t is not None:
            joints.append([(ROOT_T - joint.spine_t) * length_m, 0.0, 0.0])
        else:
            fin = fins[joint.name]
            joints.append(tube.verts[np.concatenate([fin.loops_a[0], fin.loops_b[0]])].mean(0))
    return np.asarray(joints, dtype=np.float64)


def _skin_weights(tube: BodyTube, fins: dict[str, GrownFin], num_verts: int) -> np.ndarray:
    """(V, J) weights: spine blend along the body, fins fading in over their span."""
    weights = np.zeros((num_verts, len(JOINTS)))
    ring_t = np.repeat(tube.rows_t, RING_SIZE)
    weights[1:1 + len(ring_t)] = spine_weights(ring_t)
    weights[tube.rostrum_idx] = spine_weights(np.array([0.0]))[0]
    weights[tube.notch_idx] = spine_weights(np.array([1.0]))[0]
    for name, fin in fins.items():
        num_layers = fin.loops_a.shape[0] - 1
        span_f = np.repeat(np.arange(1, num_layers + 1) / num_layers, fin.loops_a.shape[1])
        for loops in (fin.loops_a, fin.loops_b):
            base = np.tile(weights[loops[0]], (num_layers, 1))
            weights[loops[1:].ravel()] = fin_weights(base, span_f, joint_index(name))
    return weights
