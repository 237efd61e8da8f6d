"""The DOLFINx layer: the only part of wingcrack that imports DOLFINx/PETSc."""
