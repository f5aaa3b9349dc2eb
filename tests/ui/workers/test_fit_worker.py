"""The fit job (ui/workers/fit_worker.py) resolves the app's compute device first: cuda where
torch sees no GPU is bad input naming where it is chosen, before the clip is opened."""

import threading

import pytest
import torch

from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.ui.workers.fit_worker import FitJob, run_fit_job


def test_cuda_where_torch_sees_no_gpu_is_refused_naming_the_setting(tmp_path, monkeypatch):
    monkeypatch.setattr(torch.cuda, "is_available", lambda: False)
    job = FitJob(discard=threading.Event(), media=tmp_path / "missing.mp4", telemetry=None,
                 masks=tmp_path / "masks", camera=None, out_dir=tmp_path / "fit",
                 config=FitConfig(), device="cuda")
    with pytest.raises(InputError, match="^Edit → Compute device cuda: .*no CUDA GPU"):
        run_fit_job(job, lambda report: None, threading.Event())
    assert list(tmp_path.iterdir()) == []
