"""True displacement through the bindings (Scene.displace, scene/displace.h): each vertex
moved once by its program, at its corner of the first triangle that displaces, back to
object space; Displacement Only's new vertex normals; slots that move nothing."""

import numpy as np
import pytest
import whitted_native as wn
from test_program import ATTRIBUTE, INPUT, program
from test_scene import quad

POSITION = 0


def _attributes(values):
    # One RGBA corner attribute, float32[2, 3, 4], from a value per corner.
    return [np.asarray(values, np.float32).reshape(2, 3, 4)]


def test_each_vertex_moves_by_its_world_displacement_back_in_object_space():
    # The displacement is the vertex's world position: under a scale of 2 and a shift
    # of (1, 0, 0), object point p is 2p + (1, 0, 0) in the world, which is (p + (0.5, 0,
    # 0)) in object space: every vertex doubles and shifts by half a metre.
    positions, triangles = quad(-1, 1, -1, 1, 0.5)
    mesh = wn.Mesh(positions, triangles)
    to_world = np.diag([2.0, 2.0, 2.0, 1.0])
    to_world[0, 3] = 1.0
    moved = wn.Scene().displace(
        mesh, [(program([(INPUT, POSITION, 0)], [0] * 4), 0, True)], to_world
    )
    assert moved == 4
    np.testing.assert_allclose(mesh.positions, 2.0 * positions + [0.5, 0.0, 0.0], atol=1e-6)


def test_a_shared_vertex_reads_its_first_triangles_corner():
    # Vertices 0 and 2 belong to both triangles; each corner's attribute differs, and
    # the first triangle's corner moves them, each once.
    positions, triangles = quad(-1, 1, -1, 1, 0)
    corners = [[0, 0, 0.1, 0], [0, 0, 0.2, 0], [0, 0, 0.3, 0]]
    corners += [[0, 0, 0.4, 0], [0, 0, 0.5, 0], [0, 0, 0.6, 0]]
    mesh = wn.Mesh(positions, triangles, attributes=_attributes(corners))
    read = program([(INPUT, ATTRIBUTE, 0)], [0] * 4)
    assert wn.Scene().displace(mesh, [(read, 0, False)], np.eye(4)) == 4
    np.testing.assert_allclose(mesh.positions[:, 2], [0.1, 0.2, 0.3, 0.6], atol=1e-7)


@pytest.mark.parametrize("renormal", [True, False])
def test_displacement_only_gives_the_moved_faces_new_vertex_normals(renormal):
    # Vertex 2 rises by 1 over a unit square: the two faces tilt. Displacement Only
    # (renormal) gives the vertices the normalised sum of their faces' unit normals;
    # Displacement and Bump keeps the normals the mesh had.
    positions, triangles = quad(0, 1, 0, 1, 0)
    up = np.tile(np.float32([0, 0, 1]), (4, 1))
    corners = np.zeros((2, 3, 4), np.float32)
    corners[0, 2, 2] = 1.0  # triangle 0's corner 2 is vertex 2
    mesh = wn.Mesh(positions, triangles, vertex_normals=up, attributes=[corners])
    read = program([(INPUT, ATTRIBUTE, 0)], [0] * 4)
    wn.Scene().displace(mesh, [(read, 0, renormal)], np.eye(4))
    moved = mesh.positions
    assert moved[2, 2] == pytest.approx(1.0)
    if not renormal:
        np.testing.assert_array_equal(mesh.vertex_normals, up)
        return

    def face(a, b, c):
        n = np.cross(moved[b] - moved[a], moved[c] - moved[a])
        return n / np.linalg.norm(n)

    first, second = face(0, 1, 2), face(0, 2, 3)
    both = (first + second) / np.linalg.norm(first + second)
    expected = np.array([both, first, both, second])
    np.testing.assert_allclose(mesh.vertex_normals, expected, atol=1e-6)


def test_slots_without_a_displacement_move_nothing():
    # Triangle 1 (slot 1) displaces; triangle 0 (slot 0) does not: vertex 3, triangle 1's
    # own, moves, and the shared vertices 0 and 2 with it; a mesh of no displacing slot
    # is left as it was.
    positions, triangles = quad(-1, 1, -1, 1, 0)
    slots = np.array([0, 1], np.int32)
    lift = program([(INPUT, ATTRIBUTE, 0)], [0] * 4)
    corners = np.tile(np.float32([0, 0, 1, 0]), (2, 3, 1))
    mesh = wn.Mesh(positions, triangles, material_slots=slots, attributes=[corners])
    assert wn.Scene().displace(mesh, [None, (lift, 0, True)], np.eye(4)) == 3
    np.testing.assert_allclose(mesh.positions[:, 2], [1, 0, 1, 1])
    untouched = wn.Mesh(positions, triangles, material_slots=slots, attributes=[corners])
    assert wn.Scene().displace(untouched, [None], np.eye(4)) == 0
    np.testing.assert_array_equal(untouched.positions, positions)


def test_a_program_that_reads_a_missing_texture_is_refused():
    positions, triangles = quad(-1, 1, -1, 1, 0)
    image = program([(INPUT, POSITION, 0)], [0] * 4, textures=["nowhere"])
    with pytest.raises(ValueError, match="nowhere"):
        wn.Scene().displace(wn.Mesh(positions, triangles), [(image, 0, True)], np.eye(4))
