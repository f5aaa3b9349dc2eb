"""Build, inspect and export the procedural dolphin template.

  dolphinfit template build [--out PATH]     regenerate the asset (deterministic)
  dolphinfit template info [--json] [--path PATH]
  dolphinfit template export OUT.(ply|obj|glb) [--length M] [--shape PART=s,sx,sy,sz]...
                                               [--pose PART=rx,ry,rz]...

--shape takes log scales (0 = template) for a part: uniform, then along the part's own x, y, z
axes. --pose takes a part's rotation as an axis-angle vector in degrees. Parts: root, thorax,
head, tail0 … tail4, dorsal_fin, flippers, flukes.
"""

import argparse
import json
import math
from pathlib import Path

import torch

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.mesh_export import MESH_SUFFIXES, export_mesh
from dolphinfit.core.io.output_paths import check_output_file
from dolphinfit.core.limits import BODY_LENGTH_M, in_range, number
from dolphinfit.core.measure.mesh import body_length
from dolphinfit.core.model.builder import build_template
from dolphinfit.core.model.model import NUM_SHAPE_PARAMS, DolphinModel
from dolphinfit.core.model.summary import TemplateSummary, shape_targets, summarize
from dolphinfit.core.model.template import TEMPLATE_PATH, load_template, save_template


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the ``build``, ``info`` and ``export`` actions."""
    actions = parser.add_subparsers(dest="action", required=True, metavar="ACTION")
    build = actions.add_parser("build", help="regenerate the template asset")
    build.add_argument("--out", type=Path, default=TEMPLATE_PATH,
                       help="where to write it (default: the bundled asset)")
    info = actions.add_parser("info", help="print the template's figures and targets")
    info.add_argument("--json", action="store_true", help="one JSON object on stdout")
    info.add_argument("--path", type=Path, default=None, help="a template asset to read")
    export = actions.add_parser("export", help="write the (shaped, posed) mesh")
    export.add_argument("out", type=Path, help=f"output file ({', '.join(MESH_SUFFIXES)})")
    export.add_argument("--length", type=float, default=None, metavar="M",
                        help="body length in metres (uniform scale)")
    export.add_argument("--shape", action="append", default=[], metavar="PART=s,sx,sy,sz",
                        help="log scales of a part (repeatable)")
    export.add_argument("--pose", action="append", default=[], metavar="PART=rx,ry,rz",
                        help="axis-angle of a part in degrees (repeatable)")


def run(args: argparse.Namespace) -> int:
    """Dispatch to the chosen action."""
    return {"build": _build, "info": _info, "export": _export}[args.action](args)


def _build(args: argparse.Namespace) -> int:
    check_output_file(args.out, "--out ")
    template = build_template()
    save_template(template, args.out)
    summary = summarize(template)
    print(f"wrote {args.out}: {summary.num_verts} vertices, {summary.num_faces} faces, "
          f"{summary.num_joints} joints in {summary.num_groups} parts")
    return 0


def _info(args: argparse.Namespace) -> int:
    summary = summarize(load_template(args.path))
    if args.json:
        print(json.dumps(summary.to_json(), indent=2))
    else:
        print(format_summary(summary))
    return 0


def format_summary(summary: TemplateSummary) -> str:
    """Human-readable report: figures, station profile and anatomical targets."""
    lines = [
        f"length          {summary.length_m:.4f} m (rostrum tip to fluke notch)",
        f"volume          {summary.volume_m3:.4f} m³   volume / BL³ {summary.volume_per_bl3:.5f}",
        f"watertight      {summary.watertight}   consistently wound {summary.winding_consistent}",
        f"mesh            {summary.num_verts} vertices, {summary.num_faces} faces",
        f"skeleton        {summary.num_joints} joints in {summary.num_groups} parts",
        "",
        "station   width m   height m   width/BL   height/width",
    ]
    lines += [f"{s.fraction * 100:5.0f} %   {s.width_m:7.4f}   {s.height_m:8.4f}   "
              f"{s.width_bl:8.4f}   {s.hw_ratio:12.3f}" for s in summary.stations]
    lines += ["", "target                                          value     range          ok"]
    lines += [f"{c.name:46s} {c.value:7.4f}   {c.low:5.3f}–{c.high:5.3f}   "
              f"{'yes' if c.ok else 'NO'}" for c in shape_targets(summary)]
    return "\n".join(lines)


def _export(args: argparse.Namespace) -> int:
    check_output_file(args.out)
    if args.length is not None:
        in_range(args.length, BODY_LENGTH_M, "--length")
    template = load_template()
    model = DolphinModel(template, dtype=torch.float64)
    betas, pose, transl = model.zero_params(1)
    for part, values in _part_values(args.shape, model.group_names, NUM_SHAPE_PARAMS, "--shape"):
        betas[part] = values
    for part, values in _part_values(args.pose, model.group_names, 3, "--pose"):
        pose[0, part] = values * math.pi / 180.0
    if args.length is not None:
        rest_verts, _ = model.forward_rest(betas)
        current = body_length(rest_verts, model.rostrum_idx, model.notch_idx)
        betas[:, 0] += torch.log(args.length / current)
    with torch.no_grad():
        verts = model(betas, pose, transl).verts[0].numpy()
    export_mesh(args.out, verts, template.faces, template.uvs, template.face_uvs_idx,
                template.albedo)
    print(f"wrote {args.out}")
    return 0


def _part_values(items: list[str], parts: tuple[str, ...], count: int,
                 option: str) -> list[tuple[int, torch.Tensor]]:
    """Parse ``PART=a,b,c`` items into (part index, values)."""
    parsed = []
    for item in items:
        name, _, text = item.partition("=")
        if name not in parts:
            raise InputError(f"{option} {item!r}: unknown part {name!r} "
                             f"(parts: {', '.join(parts)})")
        try:
            values = [float(v) for v in text.split(",")]
        except ValueError:
            values = []
        if len(values) != count:
            raise InputError(f"{option} {item!r}: expected {count} comma-separated numbers")
        values = [number(v, f"{option} {item!r}") for v in values]
        parsed.append((parts.index(name), torch.tensor(values, dtype=torch.float64)))
    return parsed
