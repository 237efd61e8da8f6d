"""The compiled kernels (cpp_kernels/), built as the top-level module
`wingcrack_kernels` so that meshing/ uses them without importing this package."""
from wingcrack_kernels import *  # noqa: F401,F403
