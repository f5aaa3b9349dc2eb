"""Which HW table a ``--hw`` value names: the 3D model's ("model"), a CSV file, or a bundled
preset. Apart from ``hw_ratios`` because the model's table needs the mesh stack (torch),
which preset and CSV tables never load."""

from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.hw_ratios import FROM_MODEL, HWRatios, load_hw_preset, read_hw_csv


def resolve_hw(spec: str) -> HWRatios:
    """``--hw`` value → table: "model" (the template), a CSV path, or a preset name."""
    if spec == FROM_MODEL:
        from dolphinfit.core.model.hw_from_model import hw_from_template
        return hw_from_template()
    path = Path(spec)
    if path.suffix.lower() == ".csv" or path.exists():
        if not path.is_file():
            raise InputError(f"{path}: HW ratio file not found")
        return read_hw_csv(path)
    return load_hw_preset(spec)
