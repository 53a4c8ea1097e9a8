"""Meshes for oocyte_fe: the layered oocyte, verification geometries, reading and checks.

All meshes are scikit-fem triangle meshes in um (x = r, y = z when axisymmetric) with named
``subdomains`` and ``boundaries``; gmsh builds them once and they are cached by parameters.
"""

from oocyte_fe.mesh.layered import LayeredOocyte, layered_oocyte_mesh
from oocyte_fe.mesh.msh_reader import read_mesh
from oocyte_fe.mesh.quality import check_mesh, require_groups
from oocyte_fe.mesh.verification import annulus_quarter_mesh, block_mesh, spherical_shell_mesh

__all__ = [
    "LayeredOocyte",
    "annulus_quarter_mesh",
    "block_mesh",
    "check_mesh",
    "layered_oocyte_mesh",
    "read_mesh",
    "require_groups",
    "spherical_shell_mesh",
]
