"""The version of wingcrack (written into every summary.json)."""
__version__ = "0.1.0"
