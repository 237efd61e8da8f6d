"""Writing results: summary.json, field files, pictures."""
import warnings

# A title may hold any Unicode text; a character the font lacks (an emoji) is
# drawn as a box, and matplotlib's warning about it is not news for the user.
warnings.filterwarnings("ignore", message=r"Glyph \d+ .*missing from", category=UserWarning)
