"""Wing-crack propagation: the loop of the paper's Fig. 8, one concept a file:
critical_load (the load factor at which the first tip reaches KIc),
growth (one step's growth of every tip), growth_law (how far each tip
advances), fracture_set (the evolving polylines and tip states), joining
(T-junctions and the outer boundary), checkpoint and interrupt (stopping
and going on), loop (discretise -> critical load -> solve -> SIFs ->
growth -> next mesh, each step through wingcrack.step)."""
