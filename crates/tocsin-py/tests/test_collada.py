"""COLLADA files against a second reader: trimesh with pycollada, on seeded random scenes
(nested nodes with matrix / translate / rotate / scale, library nodes instanced, a geometry
placed several times or not at all, triangles, polylists and polygons, lines, Y_UP and Z_UP).
Both must place the same triangles; tocsin keeps each as written (a soup), so the faces,
the areas, the bounding boxes and the vertex sets are compared."""

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

import tocsin



def _geometry(rng, gid):
    """A random closed-ish blob of quads and triangles, as one of three primitive kinds."""
    n = int(rng.integers(4, 9))
    pts = rng.normal(size=(n, 3)) * rng.uniform(0.2, 2.0)
    kind = rng.choice(["triangles", "polylist", "polygons"])
    faces = []
    for _ in range(int(rng.integers(2, 7))):
        k = int(rng.integers(3, 5)) if kind != "triangles" else 3
        faces.append(rng.choice(n, size=k, replace=False).tolist())
    floats = " ".join(f"{x:.9g}" for x in pts.ravel())
    src = (f'<source id="{gid}-p"><float_array id="{gid}-pa" count="{3 * n}">{floats}</float_array>'
           f'<technique_common><accessor source="#{gid}-pa" count="{n}" stride="3">'
           '<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>'
           f'</accessor></technique_common></source><vertices id="{gid}-v">'
           f'<input semantic="POSITION" source="#{gid}-p"/></vertices>')
    inp = f'<input semantic="VERTEX" source="#{gid}-v" offset="0"/>'
    if kind == "triangles":
        prim = f'<triangles count="{len(faces)}">{inp}<p>{" ".join(str(i) for f in faces for i in f)}</p></triangles>'
    elif kind == "polylist":
        prim = (f'<polylist count="{len(faces)}">{inp}<vcount>{" ".join(str(len(f)) for f in faces)}</vcount>'
                f'<p>{" ".join(str(i) for f in faces for i in f)}</p></polylist>')
    else:
        ps = "".join(f'<p>{" ".join(map(str, f))}</p>' for f in faces)
        prim = f'<polygons count="{len(faces)}">{inp}{ps}</polygons>'
    line = f'<lines count="1">{inp}<p>0 1</p></lines>' if rng.random() < 0.5 else ""
    return f'<geometry id="{gid}"><mesh>{src}{prim}{line}</mesh></geometry>'


def _transforms(rng):
    out = []
    for _ in range(int(rng.integers(0, 4))):
        kind = rng.choice(["translate", "rotate", "scale", "matrix"])
        if kind == "translate":
            out.append("<translate>%s</translate>" % " ".join(f"{x:.6g}" for x in rng.normal(size=3)))
        elif kind == "rotate":
            # A unit axis: assimp and pycollada rotate about the axis as written, which is not a
            # rotation when its length is not 1; tocsin normalises it, as the specification's
            # OpenGL semantics do (a test in mesh/collada.rs).
            axis = rng.normal(size=3)
            axis /= np.linalg.norm(axis)
            out.append("<rotate>%s %.6g</rotate>" % (" ".join(f"{x:.6g}" for x in axis), rng.uniform(-180, 180)))
        elif kind == "scale":
            out.append("<scale>%s</scale>" % " ".join(f"{x:.6g}" for x in rng.uniform(0.5, 2.0, size=3)))
        else:
            q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
            m = np.eye(4)
            m[:3, :3] = q * rng.uniform(0.5, 2.0)
            m[:3, 3] = rng.normal(size=3)
            out.append("<matrix>%s</matrix>" % " ".join(f"{x:.9g}" for x in m.ravel()))
    return "".join(out)


def _node(rng, geometries, library, depth):
    inner = []
    for _ in range(int(rng.integers(1, 3))):
        r = rng.random()
        if r < 0.5:
            inner.append(f'<instance_geometry url="#{rng.choice(geometries)}"/>')
        elif r < 0.7 and library:
            inner.append(f'<instance_node url="#{rng.choice(library)}"/>')
        elif depth < 3:
            inner.append(_node(rng, geometries, library, depth + 1))
    return f"<node>{_transforms(rng)}{''.join(inner)}</node>"


def _document(rng):
    geometries = [f"g{k}" for k in range(int(rng.integers(1, 4)))]
    # One more geometry that no node places.
    lib_geo = "".join(_geometry(rng, g) for g in geometries + ["unused"])
    library = [f"lib{k}" for k in range(int(rng.integers(0, 3)))]
    lib_nodes = "".join(
        f'<node id="{n}">{_transforms(rng)}<instance_geometry url="#{rng.choice(geometries)}"/></node>'
        for n in library)
    scene = "".join(_node(rng, geometries, library, 0) for _ in range(int(rng.integers(1, 4))))
    up = rng.choice(["Y_UP", "Z_UP"])
    return ('<?xml version="1.0" encoding="utf-8"?>'
            '<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
            f'<asset><unit name="meter" meter="1"/><up_axis>{up}</up_axis></asset>'
            f"<library_geometries>{lib_geo}</library_geometries>"
            + (f"<library_nodes>{lib_nodes}</library_nodes>" if library else "")
            + f'<library_visual_scenes><visual_scene id="s">{scene}</visual_scene></library_visual_scenes>'
            '<scene><instance_visual_scene url="#s"/></scene></COLLADA>')


def test_random_scenes_match_trimesh_and_pycollada(tmp_path):
    rng = np.random.default_rng(43)
    compared = 0
    for case in range(60):
        path = tmp_path / f"scene{case}.dae"
        path.write_text(_document(rng))
        theirs = trimesh.load(path, force="mesh", process=False)
        if len(theirs.faces) == 0:
            with pytest.raises(tocsin.MeshError):
                tocsin.Mesh.load(path)  # nothing placed: no triangles
            continue
        ours = tocsin.Mesh.load(path)
        v, t = np.asarray(ours.vertices), np.asarray(ours.triangles)
        size = np.abs(theirs.vertices).max()
        assert len(t) == len(theirs.faces), case
        area = np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1).sum() / 2
        # mesh-loader reads positions as f32 (6e-8 of each), and up to six nested scales of at
        # most 2 spread that over the scene; a misplaced instance is off by its own size.
        tol = 1e-5
        assert area == pytest.approx(theirs.area, rel=tol), case
        np.testing.assert_allclose(v.min(0), theirs.bounds[0], rtol=0, atol=tol * size)
        np.testing.assert_allclose(v.max(0), theirs.bounds[1], rtol=0, atol=tol * size)
        assert cKDTree(theirs.vertices).query(v)[0].max() <= tol * size, case
        assert cKDTree(v).query(theirs.vertices)[0].max() <= tol * size, case
        compared += 1
    assert compared >= 50


def test_a_robot_link_in_collada_is_the_same_as_in_obj(tmp_path):
    """The same link written as OBJ and as COLLADA (in millimetres, placed by a node) gives
    the same distances to an obstacle."""
    box = tocsin.Mesh.box([0.05, 0.1, 0.2])
    v, t = np.asarray(box.vertices), np.asarray(box.triangles)
    (tmp_path / "link.obj").write_text(
        "".join(f"v {x} {y} {z}\n" for x, y, z in v + [0.3, 0, 0])
        + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in t))
    floats = " ".join(f"{x:.9g}" for x in (v * 1000).ravel())
    (tmp_path / "link.dae").write_text(
        '<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" '
        'version="1.4.1"><asset><unit name="millimeter" meter="0.001"/><up_axis>Y_UP</up_axis></asset>'
        f'<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" count="{v.size}">'
        f'{floats}</float_array><technique_common><accessor source="#pa" count="{len(v)}" stride="3">'
        '<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>'
        '</accessor></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/>'
        f'</vertices><triangles count="{len(t)}"><input semantic="VERTEX" source="#v" offset="0"/>'
        f'<p>{" ".join(map(str, t.ravel()))}</p></triangles></mesh></geometry></library_geometries>'
        '<library_visual_scenes><visual_scene id="s"><node><translate>300 0 0</translate>'
        '<instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>'
        '<scene><instance_visual_scene url="#s"/></scene></COLLADA>')
    robot = ("<?xml version='1.0'?><robot name='r'><link name='base'/><link name='arm'><collision>"
             "<geometry><mesh filename='link.{ext}'/></geometry></collision></link>"
             "<joint name='j' type='revolute'><parent link='base'/><child link='arm'/>"
             "<axis xyz='0 0 1'/><limit lower='-3' upper='3' effort='1' velocity='1'/></joint></robot>")
    obstacle = tocsin.Mesh.sphere(0.05, 8, 16)
    scene = tocsin.Scene()
    scene.add("ball", obstacle, np.array([[1, 0, 0, 0.38], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]))
    answers = {}
    for ext in ("obj", "dae"):
        r = tocsin.Robot.from_urdf_string(robot.format(ext=ext), base_dir=str(tmp_path))
        answers[ext] = [r.in_collision(np.array([q]), scene) for q in np.linspace(-1, 1, 41)]
    assert answers["obj"] == answers["dae"]
    assert any(answers["obj"]) and not all(answers["obj"])


MALFORMED = """<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="u" meter="1"/><up_axis>Y_UP</up_axis></asset>
<library_geometries><geometry id="g"><mesh>
<source id="gp"><float_array id="gpa" count="9">0 0 0 1 0 0 0 1 0</float_array>
<technique_common><accessor source="#gpa" count="3" stride="3"><param name="X" type="float"/>
<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="gv"><input semantic="POSITION" source="#gp"/></vertices>
<triangles count="1"><input semantic="VERTEX" source="#gv" offset="0"/><p>0 1 99</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="S"><node><instance_geometry url="#g"/></node>
</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#S"/></scene>
</COLLADA>
"""


def test_a_malformed_file_is_an_error_without_a_panic_report(tmp_path):
    """The COLLADA reader panics on an index past its array: the caller gets MeshError, and
    stderr gets no panic message or backtrace (the panic is caught quietly), in a fresh
    process with backtraces on."""
    import os
    import subprocess
    import sys

    path = tmp_path / "bad.dae"
    path.write_text(MALFORMED)
    code = (
        "import tocsin\n"
        "try:\n"
        f"    tocsin.Mesh.load({str(path)!r})\n"
        "except tocsin.MeshError as e:\n"
        "    print('MeshError', e)\n"
    )
    env = dict(os.environ, RUST_BACKTRACE="1")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("MeshError") and "malformed geometry" in r.stdout, r.stdout
    assert "panicked" not in r.stderr and "backtrace" not in r.stderr, r.stderr
