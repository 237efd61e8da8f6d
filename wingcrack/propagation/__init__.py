"""Wing-crack propagation: the loop of the paper's Fig. 8, one concept a file:
loop (discretise -> the step's load factor -> solve -> SIFs -> growth ->
next mesh, each step through wingcrack.step), loading (how each step's load
factor is found: fixed, the critical load factor), pumped (a pumped step:
the pump's loading), injection and fluid (the pump: its fluid balance, the
fluid's density; its schedule is wingcrack/schedule.py), critical_load
(the load factor at which the first tip reaches KIc), growth (one step's
growth of every tip), growth_law (how far each tip advances), fracture_set
(the evolving polylines and tip states), joining (T-junctions and the outer
boundary), patch (the circle remeshed on a fixed mesh), checkpoint
(stopping and going on)."""
