"""The frames of the growth animation (io.animation), drawn fast: one
figure per Look, whose fixed parts (the axes, their ticks and labels, the
colour bars) are drawn once; each frame is drawn over a copy of them (the
field, the pressure rims, the state bands, the fracture lines, then the
axes' frame, the legend and the title, which lie over the field), the
order of a whole drawing of the figure, so that the pixels are the same
(tests/unit/test_growing_animation.py compares them with matplotlib's own
animation writer). A frame is kept as the movie writer takes it
(io.movie): for a GIF, its pixels' indices into the GIF's one palette,
compressed (tens of kB a frame: a long run's frames stay small in the
drawing process).
"""
from __future__ import annotations

import functools
import zlib
from dataclasses import dataclass

import numpy as np

from . import fonts
from .pictures import FACE_BANDS, PRESSURE_BAR, PRESSURE_BLUES, pressure_colours

#: the figure's resolution (dots per inch): the frames' pixels
DPI = 100
#: width (points) of the face-state bands; opaque and outlined in black, as
#: the slip colour is close to magma's upper colours and a GIF's palette
#: blurs translucent ones
BAND_WIDTH = 5.0
#: width (points) of the pressure rim under a band's black outline (BAND_WIDTH
#: + 2), itself outlined in white: magma's dark colours would swallow navy
RIM_WIDTH = BAND_WIDTH + 6.0


#: the GIF's palette, one for every frame of every animation: magma's colours (the field, its colour bar),
#: a gray ramp (text, axes, white, black), the face-state bands, the pressure rims' blues and the field seen
#: through the legend; a pixel takes the entry nearest to the centre of its colour's 6-bit cell (_gif_palette). Smooth
#: gradients where a palette adaptive to each frame bands them into contours, and no palette per frame to
#: make or to compare: frames differ by their indices, which the GIF writer compares at once
MAGMA_LEVELS, GRAY_LEVELS, BLUE_LEVELS, TINTS = 64, 48, 24, 8


@functools.lru_cache(maxsize=None)
def _gif_palette() -> tuple[bytes, np.ndarray]:
    """(the palette's 768 bytes, the palette index of each colour cell:
    (64**3,) for r >> 2, g >> 2, b >> 2)."""
    import matplotlib   # lazy: start-up


    def ramp(name, lo, hi, n):
        return np.asarray(matplotlib.colormaps[name](np.linspace(lo, hi, n)))[:, :3] * 255

    bands = [[int(c[i:i + 2], 16) for i in (1, 3, 5)] for c, _ in FACE_BANDS.values()]
    legend = 0.2 * ramp("magma", 0, 1, TINTS) + 0.8 * 0.25 * 255   # the legend's box: 0.25 gray at alpha 0.8
    palette = np.vstack([ramp("magma", 0, 1, MAGMA_LEVELS), np.linspace(0, 255, GRAY_LEVELS)[:, None].repeat(3, 1),
                         bands, ramp("Blues", *PRESSURE_BLUES, BLUE_LEVELS), legend]).round().astype(np.uint8)
    palette = np.vstack([palette, palette[-1:].repeat(256 - len(palette), 0)])
    # the squared distance of each cell centre to each entry, channel by channel (ties: the first entry)
    centres = np.arange(64) * 4 + 1.5
    near = [(centres[:, None] - palette[None, :, c]) ** 2 for c in range(3)]   # (64 levels, 256 entries)
    index = np.empty((64, 64, 64), np.uint8)
    for r in range(64):
        index[r] = ((near[0][r] + near[1])[:, None, :] + near[2][None, :, :]).argmin(axis=2)
    return palette.tobytes(), index.reshape(-1)


def warm(fmt: str) -> None:
    """Make now what the frames of `fmt` need first (the GIF's palette: a
    fifth of a second, best spent while the run computes)."""
    if fmt == "gif":
        _gif_palette()


@dataclass(frozen=True)
class Frame:
    """A frame as the movie writer takes it: `size` (width, height) in
    pixels and its pixels compressed: for a GIF, their indices into the
    GIF's palette, else RGBA."""
    fmt: str
    size: tuple
    pixels: bytes

    @classmethod
    def of(cls, rgba: np.ndarray, fmt: str) -> Frame:
        """The frame of the pixels `rgba` (height, width, 4), opaque."""
        size = (rgba.shape[1], rgba.shape[0])
        if fmt != "gif":
            return cls(fmt, size, zlib.compress(rgba.tobytes(), 1))
        px = np.ascontiguousarray(rgba).view("<u4")[:, :, 0]   # r in the low byte
        index = _gif_palette()[1][((px & 0xFC) << 10) | ((px >> 4) & 0xFC0) | ((px >> 18) & 0x3F)]
        return cls(fmt, size, zlib.compress(index.tobytes(), 1))

    def image(self):
        """The frame as a Pillow image (for a GIF, in the GIF's palette)."""
        from PIL import Image   # lazy: start-up

        if self.fmt != "gif":
            return Image.frombytes("RGBA", self.size, zlib.decompress(self.pixels))
        im = Image.frombytes("P", self.size, zlib.decompress(self.pixels))
        im.putpalette(_gif_palette()[0])
        return im

    def rgba(self) -> bytes:
        """The RGBA pixels (not for a GIF: its frames are kept as palette indices)."""
        return zlib.decompress(self.pixels)


class FrameDrawer:
    """The figure of one io.animation_look.Look, its fixed parts drawn; draw()
    draws a frame over them."""

    def __init__(self, look, fmt: str):
        import matplotlib   # lazy: start-up
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib import patheffects
        from matplotlib.colors import LogNorm
        from matplotlib.lines import Line2D

        self.look, self.fmt = look, fmt
        self.norm = LogNorm(vmin=look.vmin, vmax=look.vmax)
        self.p_cmap, self.p_norm = pressure_colours(look.p_top)
        fig, ax = plt.subplots(figsize=(7.2, 6.0 if look.p_top <= 0 else 6.8), dpi=DPI)
        self.fig, self.ax = fig, ax
        try:
            fig.colorbar(plt.cm.ScalarMappable(norm=self.norm, cmap="magma"), ax=ax, label="von Mises stress (Pa)")
            if look.p_top > 0:   # below the axes, clear of the stress scale's labels
                fig.colorbar(plt.cm.ScalarMappable(norm=plt.Normalize(0.0, look.p_top / 1e6), cmap=self.p_cmap),
                             ax=ax, label=PRESSURE_BAR, orientation="horizontal", fraction=0.04, pad=0.1)
            ax.set_aspect("equal")
            ax.set_xlim(look.lo[0], look.hi[0])
            ax.set_ylim(look.lo[1], look.hi[1])
            ax.set_xlabel("x (m)")
            ax.set_ylabel("y (m)")
            # one legend for the whole run, fixed like the colour scale: the states some frame shows
            self.outline = [patheffects.Stroke(linewidth=BAND_WIDTH + 2.0, foreground="black"), patheffects.Normal()]
            handles = [Line2D([], [], color="white", lw=0.8, label="fracture")]
            handles += [Line2D([], [], color=FACE_BANDS[s][0], lw=BAND_WIDTH, solid_capstyle="butt",
                               path_effects=self.outline, label=FACE_BANDS[s][1]) for s in look.shown]
            self.rim_outline = [patheffects.Stroke(linewidth=RIM_WIDTH + 2.0, foreground="white"), patheffects.Normal()]
            if look.p_top > 0:
                handles.append(Line2D([], [], color=self.p_cmap(self.p_norm(look.p_top)), lw=RIM_WIDTH,
                                      solid_capstyle="butt", path_effects=self.rim_outline,
                                      label="pressurised (colour: p)"))
            self.legend = ax.legend(handles=handles, loc="upper right", fontsize=8, facecolor="0.25",
                                    labelcolor="white", framealpha=0.8)
            self.labels = [t.get_text() for t in self.legend.get_texts()]
            # what lies over the field is drawn with each frame, after it; the rest once, below
            self.over = list(ax.spines.values()) + [self.legend, ax.title]
            for artist in self.over:
                artist.set_animated(True)
            fig.canvas.draw()
            self.fixed = fig.canvas.copy_from_bbox(fig.bbox)
        except BaseException:
            plt.close(fig)
            raise

    def draw(self, fields, faces, title: str, drawn: list | None = None) -> Frame:
        """The frame of a step (its io.outdir.StepFields and StepFaces) under
        `title`; `drawn` (a list) gets what it banded (io.animation.animate_growth)."""
        from matplotlib.collections import LineCollection, TriMesh   # lazy: start-up
        from matplotlib.tri import Triangulation

        ax, look = self.ax, self.look
        self.fig.canvas.restore_region(self.fixed)
        v = np.clip(np.where(np.isfinite(fields.von_mises), fields.von_mises, look.vmax), look.vmin, look.vmax)
        # a TriMesh is ax.tripcolor(shading="gouraud") without its costly data limits (the view is fixed)
        field = TriMesh(Triangulation(fields.x[:, 0], fields.x[:, 1], fields.triangles), norm=self.norm,
                        cmap="magma", rasterized=True)
        field.set_array(v)
        artists = [field]
        wet = faces.pressure > 0
        rim = None
        if wet.any():
            # under the state bands and their black outline: a blue ring outside them
            rim = LineCollection(faces.lines[wet], cmap=self.p_cmap, norm=self.p_norm, linewidths=RIM_WIDTH,
                                 capstyle="butt", path_effects=self.rim_outline)
            rim.set_array(faces.pressure[wet])
            artists.append(rim)
        bands = {}
        for state, (colour, label) in FACE_BANDS.items():
            edges = faces.lines[faces.state == state]
            if len(edges):
                # under the fracture line, wide enough to show past it on either side
                bands[label] = LineCollection(edges, colors=colour, linewidths=BAND_WIDTH, capstyle="butt",
                                              path_effects=self.outline)
        artists += bands.values()
        artists.append(LineCollection(faces.lines, colors="white", linewidths=0.8))
        fonts.set_title(ax, title, fontsize=10)
        try:
            for artist in artists:
                ax.add_collection(artist, autolim=False)
                ax.draw_artist(artist)
            for artist in self.over:
                ax.draw_artist(artist)
            rgba = np.asarray(self.fig.canvas.buffer_rgba())
            frame = Frame.of(rgba, self.fmt)
        finally:
            for artist in artists:
                if artist.axes is not None:
                    artist.remove()
        if drawn is not None:
            shown = {label: np.asarray(b.get_segments(), float).reshape(-1, 3, 2) for label, b in bands.items()}
            if rim is not None:
                shown["pressurised"] = {"lines": np.asarray(rim.get_segments(), float).reshape(-1, 3, 2),
                                        "pressure": np.asarray(rim.get_array(), float)}
            shown["legend"] = self.labels
            drawn.append(shown)
        return frame

    def close(self) -> None:
        import matplotlib.pyplot as plt   # lazy: start-up

        plt.close(self.fig)
