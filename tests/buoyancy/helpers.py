"""Independent references for the buoyancy tests: exact clipping by manifold3d."""

import manifold3d
import numpy as np
import trimesh


def clipped_below(mesh, level):
    """The part of a closed trimesh below y = level, clipped by manifold3d, as a trimesh."""
    solid = manifold3d.Manifold(
        manifold3d.Mesh(
            vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
            tri_verts=np.asarray(mesh.faces, dtype=np.uint32),
        )
    )
    # trim_by_plane keeps the side the normal points to: normal (0, -1, 0), offset -level.
    part = solid.trim_by_plane((0.0, -1.0, 0.0), -level).to_mesh()
    return trimesh.Trimesh(part.vert_properties[:, :3], part.tri_verts, process=True)
