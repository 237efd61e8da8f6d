"""Wing-crack propagation: the loop of the paper's Fig. 8, one concept a file:
critical_load (the load factor at which the first tip reaches KIc),
growth_law (how far each tip advances), fracture_set (the evolving
polylines and tip states), joining (T-junctions and the outer boundary),
loop (solve -> SIFs -> growth -> remesh)."""
