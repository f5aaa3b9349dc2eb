"""Where torch computes (core.device): what each name means with and without a GPU, and the
names refused."""

import pytest
import torch

from dolphinfit.core.device import DEVICES, device_line, resolve_device
from dolphinfit.core.errors import InputError


@pytest.fixture
def sees_gpu(monkeypatch):
    """Sets whether torch sees a CUDA GPU (no GPU is touched: a device is only named)."""
    return lambda seen: monkeypatch.setattr(torch.cuda, "is_available", lambda: seen)


def test_auto_is_the_gpu_where_torch_sees_one_and_the_cpu_elsewhere(sees_gpu):
    sees_gpu(False)
    assert [resolve_device(name) for name in ("auto", "cpu")] == [torch.device("cpu")] * 2
    sees_gpu(True)
    assert [resolve_device(name).type for name in DEVICES] == ["cuda", "cpu", "cuda"]


def test_auto_on_this_machine():
    """The CPU-only install computes on the CPU, and says nothing about it."""
    device = resolve_device("auto")
    assert device.type == ("cuda" if torch.cuda.is_available() else "cpu")
    assert (device_line(device) is None) == (device.type == "cpu")


def test_cuda_without_a_gpu_is_refused_naming_the_setting(sees_gpu):
    sees_gpu(False)
    with pytest.raises(InputError, match=r"^--device cuda: torch .* sees no CUDA GPU .*auto "
                                         r"or cpu.*install guide"):
        resolve_device("cuda")
    with pytest.raises(InputError, match="^Edit → Compute device cuda: "):
        resolve_device("cuda", "Edit → Compute device")


@pytest.mark.parametrize("name", ["gpu", "CUDA", "cuda:0", "", None])
def test_other_names_are_refused(name):
    with pytest.raises(InputError, match=r"^--device: one of auto, cpu, cuda, got"):
        resolve_device(name)
