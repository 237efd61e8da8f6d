"""Neutral process helpers: long-lived worker processes with time limits
(procs.worker). Imports neither wingcrack nor meshing, which both use it."""
