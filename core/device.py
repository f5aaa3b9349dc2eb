"""Where torch computes: the CPU, or a CUDA GPU when the installed torch sees one.

The user names a device (``--device``, the app's Edit → Compute device): ``auto`` is the GPU
when torch sees one and the CPU otherwise, ``cpu`` and ``cuda`` force one. The fit, the edge
network of the mask tracker and its training run there; the salient network (ONNX Runtime)
always runs on the CPU. A result does not record where it was computed: on the CPU it is the
same to the last bit as before devices existed, on a GPU the same within float rounding.

torch is imported only when a name is resolved, so the app can offer the names without
loading it.
"""

from typing import TYPE_CHECKING

from dolphinfit.core.errors import InputError
from dolphinfit.core.limits import one_of

if TYPE_CHECKING:
    import torch

AUTO, CPU, CUDA = "auto", "cpu", "cuda"
DEVICES = (AUTO, CPU, CUDA)
DEFAULT_DEVICE = AUTO   # the CPU on the CPU-only install (docs/how-to/install.md)


def cuda_available() -> bool:
    """Whether the installed torch sees a CUDA GPU (imports torch)."""
    import torch

    return torch.cuda.is_available()


def resolve_device(name: str, where: str = "--device") -> "torch.device":
    """The torch device that ``name`` (one of ``DEVICES``) means here; InputError naming
    ``where`` for another name, or for ``cuda`` where torch sees no CUDA GPU."""
    one_of(name, DEVICES, where)
    import torch

    if torch.cuda.is_available():
        return torch.device(CPU if name == CPU else CUDA)
    if name == CUDA:
        build = "a CPU-only build" if torch.version.cuda is None else "no GPU or driver found"
        raise InputError(f"{where} {CUDA}: torch {torch.__version__} sees no CUDA GPU "
                         f"({build}); choose {AUTO} or {CPU}, or install a CUDA build of "
                         f"torch (the manual's install guide)")
    return torch.device(CPU)


def device_line(device: "torch.device") -> str | None:
    """A line naming the GPU that ``device`` is, for the user; None for the CPU (nothing to
    say)."""
    if device.type != CUDA:
        return None
    import torch

    return f"computing on the GPU: {torch.cuda.get_device_name(device)}"
