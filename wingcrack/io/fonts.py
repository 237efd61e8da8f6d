"""Text the pictures' font cannot draw (a title in Chinese, an emoji): the
installed fonts that have those characters, to fall back on (matplotlib
draws each glyph from the first font of a family list that has it), or the
characters that none has, so that the user is told once instead of seeing
boxes and a matplotlib warning per glyph."""
from __future__ import annotations

import warnings
from contextlib import contextmanager
from functools import lru_cache

#: the pictures' font (matplotlib's default)
BASE = "DejaVu Sans"


@lru_cache(maxsize=None)
def _charmap(path: str) -> frozenset:
    from matplotlib.ft2font import FT2Font  # here: matplotlib loads with the first picture only

    try:
        return frozenset(FT2Font(path).get_charmap())
    except (OSError, RuntimeError):   # a font file matplotlib lists but cannot open
        return frozenset()


def _drawn(c: str) -> bool:
    """Whether c needs a glyph at all (not a space, a control or a joiner)."""
    return not c.isspace() and c.isprintable() and c not in "\u200d\ufe0f"


@lru_cache(maxsize=64)
def fallback(text: str) -> tuple[tuple[str, ...], str]:
    """(families, missing): the font family list that draws `text` (BASE
    first, then installed fonts for the characters BASE lacks, in the order
    matplotlib lists them), and the characters no installed font has."""
    import matplotlib.font_manager as fm  # here: matplotlib loads with the first picture only

    need = set(c for c in text if _drawn(c) and ord(c) not in _charmap(fm.findfont(BASE)))
    families = [BASE]
    for f in fm.fontManager.ttflist:
        if not need:
            break
        covered = {c for c in need if ord(c) in _charmap(f.fname)}
        if covered:
            need -= covered
            if f.name not in families:
                families.append(f.name)
    return tuple(families), "".join(dict.fromkeys(c for c in text if c in need))   # in the title's order


def title_warning(title: str) -> str | None:
    """The one warning for a title with characters no installed font has."""
    missing = fallback(title)[1]
    if not missing:
        return None
    return (f"the title's characters {missing} are in no installed font: the pictures draw them as boxes "
            "(install a font that has them, for example Debian's fonts-noto-cjk or fonts-noto-color-emoji)")


def set_title(ax, text: str, **kwargs):
    """ax.set_title with the fallback families of `text` (BASE alone, the
    default, when BASE has every character)."""
    return ax.set_title(text, fontfamily=list(fallback(text)[0]), **kwargs)


@contextmanager
def quiet_glyphs():
    """matplotlib's warning per glyph that no font has, silenced while the
    pictures are drawn: title_warning says it once, in the summary."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Glyph .* missing from", category=UserWarning)
        yield
