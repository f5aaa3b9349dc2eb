"""The sweep of ``bench masks --sweep``: one family of clips, one thing changed at a time."""

from dataclasses import replace

from dolphinfit.core.bench.sweep import BASE, CONTRASTS, sweep_points


def test_each_point_changes_one_thing_from_the_base():
    points = sweep_points()
    assert points[0].factor == "base" and points[0].config == BASE
    by_factor = {}
    for point in points[1:]:
        by_factor.setdefault(point.factor, []).append(point)
    assert sorted({BASE.blur_px, *(p.config.blur_px for p in by_factor["blur"])}) == \
        [0.3, 0.6, 1.0, 1.5, 2.0]
    assert [p.contrast_levels for p in by_factor["contrast"][:len(CONTRASTS)]] == \
        [5.0, 10.0, 20.0, 40.0, 60.0]
    assert {p.value for p in by_factor["contrast"][len(CONTRASTS):]} == \
        {"dark over dark", "light over light"}
    assert sorted({BASE.crf, *(p.config.crf for p in by_factor["compression"])}) == \
        [18, 23, 28, 35]
    assert sorted({BASE.supersample, *(p.config.supersample for p in by_factor["delivered"])}) \
        == [1, 2, 4]
    assert len(by_factor["width"]) == 4 and len(by_factor["noise"]) == 2
    for factor in ("blur", "noise", "compression", "delivered", "width"):
        for point in by_factor[factor]:
            changed = [name for name, value in vars(point.config).items()
                       if value != getattr(BASE, name)]
            assert len(changed) == 1, (point.value, changed)
    assert replace(BASE).codec == "h264"
