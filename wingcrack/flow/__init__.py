"""Flow along the fractures: a compressible fluid in the faces' network
under the cubic law, one backward-Euler time step at a time (network.py:
where the flow lives; lubrication.py: the step). On arrays only: the
mechanics it is coupled with reach it as openings and their compliance."""
