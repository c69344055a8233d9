"""The campaign report's histograms when every scan gives (nearly) the same number: identical
scans made matplotlib refuse "Too many bins for data range" and the campaign report fail."""

import numpy as np
import pytest

from pipelines.campaign.report import _hist_bins


@pytest.mark.parametrize(
    "values",
    [
        [2.5e-4, 2.5e-4],  # identical scans
        [1.0, 1.0 + 2e-16, 1.0 - 2e-16],  # a few ulps apart
        [0.0, 0.0, 0.0],  # all zero
    ],
)
def test_agreeing_values_draw_one_bar(values):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = np.array(values)
    kw = _hist_bins(x, x.size)
    fig, ax = plt.subplots()
    counts, edges, _ = ax.hist(x, **kw)
    plt.close(fig)
    assert counts.sum() == x.size and kw["bins"] == 1
    assert edges[0] <= x.min() and edges[-1] >= x.max()


def test_spread_values_keep_the_sqrt_rule():
    x = np.linspace(0.1, 0.9, 50)
    assert _hist_bins(x, x.size) == {"bins": 8}
