"""Parametric cage geometry and its gmsh mesh (tagged tetrahedra, order 1 or 2).

Nothing here imports gmsh at module level: `flexbearing.mesh.cage_geometry` is a plain-Python
description of the cage that the multibody model reads too.
"""
