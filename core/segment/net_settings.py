"""The network tracker's settings (core.segment.net_tracker's module doc says what each
step does with them)."""

from dataclasses import dataclass

EDGE_STEPS = ("network", "colour")
# a component this much larger than the animal was holds another animal too (``own_body``)
PAIR_AREA_RATIO = 1.6


@dataclass(frozen=True)
class NetSettings:
    """Tuning of the network tracker (defaults measured with ``dolphinfit bench masks``)."""

    context: float = 0.5             # crop margin on each side, × the mask's longer side
    threshold: float = 0.5           # saliency from which a pixel is animal
    near_fraction: float = 0.12      # kept within this × longer side of the prediction
    min_near_px: int = 6
    gap_px: int = 2                  # parts this close to the body belong to it
    band_px: int = 3                 # outline band re-decided by colour
    smoothing_sigma_px: float = 0.8  # Gaussian smoothing of the coverage map
    min_separation: float = 2.0      # colour separation (pooled SDs) needed for the edge step
    model_rate: float = 0.2          # running update of the reference area
    lost_area_ratio: float = 0.4
    lost_separation_ratio: float = 0.5
    reacquire_area_range: tuple[float, float] = (0.5, 2.0)
    search_growth: float = 1.6       # the window's growth per step while lost
    first_window_fraction: float = 0.3   # a click's first window, × the frame's shorter side
    seed_rounds: int = 3             # re-windowings around the clicked animal
    # the automatic seed's tiles, × the frame's shorter side: in a whole-height tile a 2 m
    # animal from 25 m (grey_green_high) was too small for the network to see
    tile_fraction: float = 0.5
    focus_fraction: float = 0.25     # faded out beyond this × its length from its prediction
    fade_fraction: float = 0.15      # over this × its length
    follow_iou: float = 0.8          # below this overlap with its prediction, look again
    max_area_ratio: float = PAIR_AREA_RATIO  # larger than this × its area: merged with another
    edges: str = "network"           # the outline step (module doc, step 3): EDGE_STEPS
    fit_outline: bool = True         # the outline moved to the image's edge (step 6)
    # longer than this, the animal is tracked downscaled (``working_scale``): the bench
    # suite's dolphins are 100–500 px long at 1080p and 4K, a whale near the drone thousands
    max_length_px: int = 640
