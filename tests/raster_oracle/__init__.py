"""An independent float64 NumPy reference rasterizer for brdfpy's renderer (``brdfpy.Scene.render``).

Written from first principles and the conventions of ``shared/bench/SCENE.md`` and seed 004 (constant,
Gouraud and Phong shading, quadratic normal interpolation after van Overveld & Wyvill 1997, vertex
normals, Newell's method), NOT from the Rust sources. It is slow on purpose: one Python loop over
triangles, vectorised over the pixels of each triangle's bounding box; meant for images of a few
thousand pixels. Nothing here imports ``brdfpy``; materials are shaded through the BRDF oracle
(``oracle.models.evaluate(..., quantity="shade")``).

Modules
-------
camera     look-at view matrix, gluPerspective and orthographic projections, the view vector
geometry   face normals (cross product, Newell), vertex normals (equal / area / angle weights), the
           SCENE.md icosphere subdivision, small procedural meshes for the tests
lights     directional, point and spot lights, attenuation ``1/(c1 + c2 d + c3 d^2)``
clip       homogeneous near/far clipping (Sutherland-Hodgman in clip space)
raster     the rasterizer: viewport, top-left fill rule, perspective-correct barycentrics, depth test,
           culling, flat / Gouraud / Phong / quadratic-normal shading, and per-pixel edge distances
raycast    the ideal sphere of SCENE.md, ray cast analytically
scene      the canonical scene of SCENE.md
"""

from raster_oracle import camera, clip, geometry, lights, raster, raycast, scene

__all__ = ["camera", "clip", "geometry", "lights", "raster", "raycast", "scene"]
