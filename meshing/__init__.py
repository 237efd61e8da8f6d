"""Conforming second-order crack meshes with gmsh (no DOLFINx here)."""
