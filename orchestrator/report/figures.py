"""What every figure of a run's report shares: matplotlib off-screen (Agg), the page size and
type sizes, saving a figure as PNG, and the small drawing helpers (an empty panel that says
why, legends with each label once, a note in a corner).

Every PNG is at most :data:`WIDTH_IN` wide at :data:`DPI` (1,575 px, a report page at 100 %),
no text under :data:`SMALL` points, every drawn line in a legend.
"""

from __future__ import annotations

import io
import logging
import textwrap
from pathlib import Path

from orchestrator.core.files import write_bytes_atomic

__all__ = ["DPI", "SMALL", "WIDTH_IN", "empty", "legend", "legend_axes", "legend_handles", "note", "pyplot",
           "save_figure"]

#: Every PNG at DPI from a figure at most WIDTH_IN wide: 1,575 px, a report's page width
#: at 100 %; no text smaller than SMALL points (legends, ticks, notes).
DPI = 150
WIDTH_IN = 10.5
SMALL = 9


def _not_the_equal_aspect_notice(record: logging.LogRecord) -> bool:
    """Plan views fix both limits (the flume's reach) and an equal aspect: matplotlib then widens
    one range to keep the aspect, as intended, and says so on every draw."""
    return not record.getMessage().startswith("Ignoring fixed")


def pyplot():
    """matplotlib.pyplot on the Agg backend (no display)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    base = logging.getLogger("matplotlib.axes._base")
    if _not_the_equal_aspect_notice not in base.filters:
        base.addFilter(_not_the_equal_aspect_notice)
    return plt


def save_figure(fig, path: Path) -> Path:
    """The figure as a PNG at :data:`DPI`, written atomically; the figure is closed."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    pyplot().close(fig)
    return write_bytes_atomic(path, buffer.getvalue())


def empty(ax, message: str) -> None:
    """A panel with nothing to show: the message in its middle, no ticks."""
    ax.text(0.5, 0.5, message, ha="center", va="center", transform=ax.transAxes, fontsize=11, wrap=True)
    ax.set_xticks([])
    ax.set_yticks([])


def legend_handles(*axes) -> dict:
    """Each label of the axes' lines, patches and collections once, with its first artist."""
    out: dict = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            out.setdefault(label, handle)
    return out


def legend(ax, **kwargs):
    """A legend with each label once (repeated markers such as impact times share one entry)."""
    kwargs.setdefault("fontsize", SMALL)
    entries = legend_handles(ax)
    return ax.legend(list(entries.values()), list(entries), **kwargs) if entries else None


def legend_axes(ax, sources, ncol: int = 3) -> None:
    """A legend alone in ``ax`` (its frame hidden) for the lines of every axes in ``sources``."""
    ax.axis("off")
    entries = legend_handles(*sources)
    if entries:
        ax.legend(list(entries.values()), list(entries), loc="center", ncol=ncol, fontsize=SMALL, frameon=False)


def note(ax, lines: list[str], width: int = 60, left: bool = False) -> None:
    """What a panel lacks and why, in an upper corner (the right one unless ``left``)."""
    if lines:
        text = "\n".join(textwrap.fill(line, width) for line in lines)
        ax.text(0.01 if left else 0.99, 0.97, text, transform=ax.transAxes, ha="left" if left else "right",
                va="top", fontsize=SMALL,
                bbox={"boxstyle": "round", "facecolor": "white", "edgecolor": "0.6", "alpha": 0.9}, zorder=6)
