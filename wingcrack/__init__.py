"""wingcrack: wing-crack growth from pre-existing fractures with contact."""
__version__ = "0.1.0"
