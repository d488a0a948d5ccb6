"""A cage from CAD (STEP or BREP, gmsh's OpenCASCADE kernel): its pockets and guide land found
from the geometry, matched to the bearing, meshed and tagged as the parametric cage.

What is found (every boundary face is sampled, `_sample_face`, with its normals):

* ring cylinders: faces whose normals all meet the bearing axis x at right angles (axis x,
  through the origin) at one radius r: the outside (largest r), the bore (smallest r), lands
  and relief floors in between;
* side faces: planes normal to x at the cage's two axial ends;
* pocket walls: a sphere (every normal passes through one point: its centre, by least squares)
  centred near the pitch circle, or a cylinder whose axis is radial (every normal meets one
  line through the origin normal to x: the axis is the direction orthogonal to all normals),
  or a cone whose axis is radial (every normal makes one angle with the axis; the apex on the
  radial line: pocket_shape "conical", its half-angle signed + when it widens outwards and the
  pocket diameter that of the sphere about the pitch point it is tangent to), or an elliptic
  cylinder whose axis is radial (normals orthogonal to the axis, its distance not constant; the
  section's axes along x and the direction of rotation: pocket_shape "elliptical", the axial
  and the circumferential diameter); `fit_face` has the equations. A cone or elliptic cylinder
  about a line normal to x that misses the bearing axis, or an ellipse turned from the
  axial/circumferential directions, is refused naming the field, unless it passes the bearing
  axis farther than its own radius (a hole elsewhere: another face); faces of one pocket share
  its azimuth;
* the guide surface: for guidance "outer" the ring cylinder(s) at the largest radius, for
  "inner" at the smallest; "balls" needs none.

Named groups win over the search when the file has them (`named_groups`): physical surface groups
`pocket_1` … `pocket_N` (one per pocket, any numbering; or one group `pockets` holding them all)
and `guide` (or `land`). gmsh 4.8 keeps no face names in STEP or BREP (neither on reading nor on
writing), so the names come in a gmsh `.geo` file that merges the STEP or BREP and names its faces
(`Merge "cage.step"; Physical Surface("pocket_1") = {12};`) or draws the cage itself. Each named
face must still be what its name says by its geometry (a pocket wall: a sphere or a radial
cylinder; the land: a cylinder about the bearing axis on the side the guidance needs), or the
file is refused in one line naming the group; faces the geometry would take for pockets but the
names do not are left as other faces. `CadCage.found_by` says which way each surface was found.

The bearing decides what matches: one pocket per ball, equally spaced (the model turns the CAD
so pocket 0 sits at +y), each centred on the pitch circle in the mid-plane within a tenth of the
pocket clearance, all of one diameter larger than the ball. Anything else is refused with the one
line of `InputError` that names what is missing. Units: a STEP file carries its own (OCC reads
it into millimetres, scaled to metres here; `step_length_unit` reports it); a BREP file has none
and needs `unit`.

The result, `CadCage`, holds the equivalent parametric geometry (diameters, width, pocket count,
diameter, shape and centre circle, guidance, land width), which the dynamics and the reduction
read, and what was found, which the command line prints.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import re
import stat
import sys
import tempfile
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from flexbearing.common.validation import InputError
from .cage_geometry import GUIDANCES, CageGeometry, PAPER_CAGE
from . import cage_mesh as CM
from .face_fit import fit_face
from flexbearing.common.cache import cache_dir, content_hash, write_text_atomic
from flexbearing.common.materials import Material

CAD_SUFFIXES = {".step": "step", ".stp": "step", ".brep": "brep", ".brp": "brep", ".geo": "geo"}
UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 25.4e-3}
# Geometric tolerance of the face fits, relative to the cage's outside radius: CAD kernels model
# to ~1e-7 of a part's size; 1e-5 leaves room for STEP's text round-off.
FIT_TOL = 1e-5


@dataclass(frozen=True)
class FoundPocket:
    """One pocket as found in the CAD: azimuth (rad, from +y towards +z, after the turn that puts
    pocket 0 at +y), centre (m; a cylinder's, a cone's or an elliptic cylinder's is its axis at the
    pitch radius), shape, diameter (m; a cone's: CageGeometry.pocket_diameter, the diameter of the
    sphere about the centre it is tangent to; an ellipse's: along the bearing axis), faces; a
    conical pocket's half-angle (rad, > 0 wider at the outside), an elliptical pocket's diameter in
    the direction of rotation (m)."""
    azimuth: float
    centre: tuple
    shape: str
    diameter: float
    faces: tuple
    cone_angle: float = 0.0
    circumferential_diameter: float = 0.0


@dataclass(frozen=True)
class CadCage:
    """What the CAD cage is (module docstring)."""
    geometry: CageGeometry            # the equivalent parametric cage the dynamics reads
    pockets: tuple                    # FoundPocket, in azimuth order
    ring_cylinders: tuple             # (radius m, x_min m, x_max m of the sampled points, n faces), by radius
    guide_faces: tuple                # surface tags of the guide surface
    turned_by: float                  # rad about +x applied to put pocket 0 at +y
    unit: str
    source: str
    scale: float                      # metres per unit of the gmsh model's numbers
    groups: dict = field(default_factory=dict)   # name -> surface tags
    found_by: dict = field(default_factory=dict)  # "pockets" / "guide" -> how they were found
    notes: tuple = ()                             # printed under the first line (a unit given over the file's)

    def report_lines(self, pitch_diameter: float, ball_diameter: float) -> list[str]:
        g = self.geometry
        cp = 0.5 * (g.pocket_diameter - ball_diameter)
        lines = [f"{self.source}: unit {self.unit}; outside {g.outside_diameter * 1e3:.3f} mm, bore "
                 f"{g.bore_diameter * 1e3:.3f} mm, width {g.width * 1e3:.3f} mm; turned "
                 f"{math.degrees(self.turned_by):.3f}° about x so pocket 0 is at +y",
                 *self.notes,
                 f"{len(self.pockets)} {g.pocket_shape} pockets of {g.pocket_diameter * 1e3:.3f} mm"
                 + self._shape_words() +
                 f" (clearance {cp * 1e6:.1f} µm on a {ball_diameter * 1e3:.3f} mm ball)"]
        lines += [f"{what} found by {how}" for what, how in self.found_by.items() if what != "unused"]
        if "unused" in self.found_by:
            lines.append(f"named groups not used (not pocket_<n>, pockets, guide or land): {self.found_by['unused']}")
        for k, p in enumerate(self.pockets):
            c = np.array(p.centre)
            lines.append(f"  pocket {k:2d}: azimuth {math.degrees(p.azimuth):8.3f}°, centre radius "
                         f"{np.hypot(c[1], c[2]) * 1e3:.4f} mm (pitch {0.5 * pitch_diameter * 1e3:.4f}), "
                         f"x {c[0] * 1e3:+.4f} mm, {len(p.faces)} face(s)")
        for r, x0, x1, n in self.ring_cylinders:
            lines.append(f"  ring cylinder r = {r * 1e3:.3f} mm, x {x0 * 1e3:+.3f} .. {x1 * 1e3:+.3f} mm, {n} face(s)")
        if g.guidance == "balls":
            lines.append("guidance balls: no land")
        else:
            where = "outside" if g.guidance == "outer" else "bore"
            lines.append(f"guidance {g.guidance}: {len(self.guide_faces)} land face(s) on the {where}, "
                         f"land width {g.land_width * 1e3:.3f} mm"
                         + (f" x 2 (relief {g.relief_depth * 1e3:.3f} mm deep)" if g.relief_depth > 0 else ""))
        return lines


    def _shape_words(self) -> str:
        """What the pocket diameter is and the shape's own numbers (none for cylinders, spheres)."""
        g = self.geometry
        if g.pocket_shape == "conical":
            b = g.pocket_cone_angle
            return (f" at the pitch circle (the sphere the cone is tangent to), half-angle "
                    f"{math.degrees(b):+.4f}° (wider at the {'outside' if b > 0 else 'bore'})")
        if g.pocket_shape == "elliptical":
            return f" axial × {g.pocket_circumferential_diameter * 1e3:.3f} mm circumferential"
        return ""


def cad_kind(path) -> str:
    kind = CAD_SUFFIXES.get(Path(path).suffix.lower())
    if kind is None:
        raise InputError(f"cage.cad = {str(path)!r}: not a CAD file; allowed: STEP (.step, .stp), "
                         f"BREP (.brep, .brp) or a gmsh .geo naming the faces of one")
    return kind


# ---------------------------------------------------------------- the CAD input, read as data
# A gmsh .geo is a program (System runs a shell command, Printf > writes a file, Exit, loops,
# Include ...): it is never given to gmsh. It is parsed here, and only this subset is read:
#   SetFactory("OpenCASCADE");                    (optional)
#   Merge "cage.step";                            (exactly one: a STEP or BREP in the .geo's folder)
#   Physical Surface("pocket_1") = {12, 14:16};   (named face groups; Physical Volume too)
# with // and /* */ comments. Anything else is refused in one line naming the statement and its
# line, before gmsh runs; the geometry is then built from these facts (the STEP/BREP imported,
# the groups applied by their face numbers: gmsh numbers a merged STEP's faces as importShapes does).
MAX_GEO_BYTES = 1 << 20          # a naming file of ~20,000 groups; larger is not a cage's .geo
GEO_SUBSET = ('SetFactory("OpenCASCADE");, one Merge "FILE.step"; (a STEP or BREP file in the .geo\'s '
              'folder) and Physical Surface("name") = {faces};')
_GEO_TOKEN = re.compile(r'(?P<ws>\s+)|(?P<lc>//[^\n]*)|(?P<bc>/\*.*?\*/)|(?P<str>"[^"\n]*")'
                        r'|(?P<id>[A-Za-z_][A-Za-z0-9_]*)|(?P<num>[0-9]+)|(?P<p>[(){},;=:])', re.S)
_SAFE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.+ -]*")
_GROUP_DIMS = {"Surface": 2, "Volume": 3}
MAX_FACE_RANGE = 100_000


@dataclass(frozen=True)
class GeoGroup:
    """A named physical group of a cage .geo: its name, dimension (2 faces, 3 volumes), entity
    tags and the line it is on."""
    name: str
    dim: int
    tags: tuple
    line: int


@dataclass(frozen=True)
class CadSource:
    """A CAD cage input read once, as data: the file the user named (`path`), the STEP or BREP
    it is or merges (`shape_file`, `kind`, its bytes `data`), the .geo's named groups, and the
    sha256 of every file the geometry reads (`digests`: the CAD cache's key)."""
    path: Path
    kind: str
    shape_file: Path
    data: bytes
    groups: tuple = ()
    digests: dict = field(default_factory=dict)


def _geo_refusal(source: str, line: int, what: str) -> InputError:
    return InputError(f"cage.cad = {source!r}: line {line}: {what}; a cage .geo may hold only "
                      f"{GEO_SUBSET} (it is read as data, never run)")


def _statement_text(text: str, start: int, end: int) -> str:
    """The statement as written (its first line, spaces collapsed, at most 60 characters)."""
    nl = text.find("\n", start)
    s = " ".join(text[start:end if nl < 0 else min(end, nl)].split())
    return s if len(s) <= 60 else s[:57] + "..."


def parse_cage_geo(text: str, source: str) -> tuple[str, int, tuple]:
    """(merged file name, its line, named groups) of a cage .geo (`text`), parsed by the subset
    above; InputError naming the first statement outside it (and its line) otherwise."""
    tokens, pos = [], 0                  # (kind, value, line, start offset)
    while pos < len(text):
        m = _GEO_TOKEN.match(text, pos)
        line = text.count("\n", 0, pos) + 1
        if m is None:
            if text.startswith('"', pos):
                raise _geo_refusal(source, line, f"a string not closed on its line "
                                                 f"({text[pos:pos + 30].splitlines()[0]!r})")
            if text.startswith("/*", pos):
                raise _geo_refusal(source, line, "a /* comment never closed")
            # the statement this character is in, from its first token (after the last ';')
            last = max((k for k, t in enumerate(tokens) if t[1] == ";"), default=-1)
            start = tokens[last + 1][3] if last + 1 < len(tokens) else pos
            raise _geo_refusal(source, text.count("\n", 0, start) + 1,
                               f"{_statement_text(text, start, len(text))} is not allowed (character {text[pos]!r})")
        if m.lastgroup not in ("ws", "lc", "bc"):
            tokens.append((m.lastgroup, m.group(), line, pos))
        pos = m.end()
    merge, groups, names = None, [], set()
    stmt: list = []
    for tok in tokens:
        if tok[1] != ";":
            stmt.append(tok)
            continue
        if not stmt:
            continue
        line = stmt[0][2]
        said = _statement_text(text, stmt[0][3], tok[3] + 1)
        heads = ("SetFactory", "Merge", "Physical")
        if stmt[0][1] in heads and any(t[1] in heads and t[2] > stmt[k - 1][2]
                                       for k, t in enumerate(stmt) if k > 0):   # the ';' is missing
            raise _geo_refusal(source, line, f"{said} is not ended by ';'")
        kinds = [k for k, _, _, _ in stmt]
        vals = [v for _, v, _, _ in stmt]
        if vals == ["SetFactory", "(", '"OpenCASCADE"', ")"]:
            pass
        elif vals[0] == "Merge" and (kinds[1:] == ["str"] or vals[1:] == ["(", vals[2], ")"] and kinds[2] == "str"):
            if merge is not None:
                raise _geo_refusal(source, line, f"{said} is a second Merge (the first on line {merge[1]})")
            merge = (vals[1] if kinds[1] == "str" else vals[2])[1:-1], line
        elif vals[:2] in (["Physical", "Surface"], ["Physical", "Volume"]):
            groups.append(_physical_group(stmt, said, source, names))
        else:
            raise _geo_refusal(source, line, f"{said} is not allowed")
        stmt = []
    if stmt:
        raise _geo_refusal(source, stmt[0][2], f"{_statement_text(text, stmt[0][3], len(text))} is not "
                                               f"ended by ';'")
    if merge is None:
        raise InputError(f"cage.cad = {source!r}: it merges no STEP or BREP file (Merge \"cage.step\";): "
                         f"a .geo that draws the cage is not read; export the cage as STEP and name its "
                         f"faces in a .geo that merges it")
    return merge[0], merge[1], tuple(groups)


def _physical_group(stmt: list, said: str, source: str, names: set) -> GeoGroup:
    """Physical Surface|Volume("name"[, tag]) = {n, n:m, ...}"""
    kinds = [k for k, _, _, _ in stmt]
    vals = [v for _, v, _, _ in stmt]
    line = stmt[0][2]
    head = ["id", "id", "p", "str"]
    if kinds[:4] != head or vals[2] != "(":
        raise _geo_refusal(source, line, f"{said} is not allowed (a group needs a name: "
                                         f"Physical Surface(\"pocket_1\") = {{12}};)")
    i = 4
    if vals[i:i + 2] and vals[i] == "," and kinds[i + 1:i + 2] == ["num"]:
        i += 2                                          # an explicit group tag: not needed, ignored
    if vals[i:i + 3] != [")", "=", "{"] or vals[-1] != "}":
        raise _geo_refusal(source, line, f"{said} is not allowed (Physical Surface(\"name\") = {{faces}};)")
    body = stmt[i + 3:-1]
    tags: list[int] = []
    j = 0
    while j < len(body):
        if body[j][0] != "num":
            raise _geo_refusal(source, line, f"{said}: {body[j][1]!r} is not a face number")
        a = int(body[j][1])
        if j + 2 < len(body) + 1 and body[j + 1:j + 2] and body[j + 1][1] == ":":
            if j + 2 >= len(body) or body[j + 2][0] != "num":
                raise _geo_refusal(source, line, f"{said}: a range needs two numbers (12:16)")
            b = int(body[j + 2][1])
            if not a <= b <= a + MAX_FACE_RANGE:
                raise _geo_refusal(source, line, f"{said}: range {a}:{b} (allowed: a <= b <= a + {MAX_FACE_RANGE})")
            tags.extend(range(a, b + 1))
            j += 3
        else:
            tags.append(a)
            j += 1
        if j < len(body):
            if body[j][1] != ",":
                raise _geo_refusal(source, line, f"{said}: {body[j][1]!r} where ',' was expected")
            j += 1
            if j == len(body):
                raise _geo_refusal(source, line, f"{said}: a list ending in ','")
    if not tags:
        raise _geo_refusal(source, line, f"{said}: an empty group")
    name = vals[3][1:-1]
    if not name.strip() or name in names:
        raise _geo_refusal(source, line, f"{said}: group name {name!r} " + ("empty" if not name.strip() else "given twice"))
    names.add(name)
    return GeoGroup(name, _GROUP_DIMS[vals[1]], tuple(tags), line)


def _read_regular(path: Path, source: str, what: str, follow: bool, limit: int | None = None) -> bytes:
    """The bytes of a regular file, opened without blocking (a FIFO never waits for a writer) and,
    for a file named inside a .geo, without following a link; InputError naming it otherwise."""
    flags = os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | (0 if follow else os.O_NOFOLLOW)
    try:
        if not follow and os.path.islink(path):
            raise InputError(f"cage.cad = {source!r}: {what} {str(path)!r} is a symbolic link; a cage "
                             f".geo merges a file of its own folder, not a link")
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise InputError(f"cage.cad = {source!r}: {what} {str(path)!r}: no such file") from None
    except OSError as exc:
        raise InputError(f"cage.cad = {source!r}: {what} {str(path)!r} cannot be read ({exc.strerror})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"cage.cad = {source!r}: {what} {str(path)!r} is not a regular file (a folder, "
                             f"device or pipe); give the CAD file itself")
        if limit is not None and st.st_size > limit:
            raise InputError(f"cage.cad = {source!r}: {what} {str(path)!r} is {st.st_size:,} bytes, more than "
                             f"a cage .geo's {limit:,}: not a naming file")
        os.set_blocking(fd, True)
        chunks = []
        while True:
            b = os.read(fd, 1 << 20)
            if not b:
                break
            chunks.append(b)
        return b"".join(chunks)
    finally:
        os.close(fd)


def _check_shape_data(data: bytes, kind: str, path: Path, source: str) -> None:
    """An empty, truncated or foreign STEP/BREP refused in one line before gmsh reads it."""
    head = f"cage.cad = {source!r}: " + ("the file" if str(path) == source else f"the merged file {path.name!r}")
    if not data.strip():
        raise InputError(f"{head} is empty")
    if kind == "step":
        if not data.lstrip().startswith(b"ISO-10303-21;"):
            raise InputError(f"{head} is not a STEP file (it does not begin with ISO-10303-21;)")
        if not data.rstrip().endswith(b"END-ISO-10303-21;"):
            raise InputError(f"{head} is truncated or damaged: a STEP file ends with END-ISO-10303-21; "
                             f"({len(data):,} bytes read)")
    elif b"CASCADE Topology" not in data[:512]:
        raise InputError(f"{head} is not an OpenCASCADE BREP file (no 'CASCADE Topology' header)")


def read_cad_source(path) -> CadSource:
    """Read a CAD cage input as data (module section above): a STEP or BREP file, or a cage .geo
    and the one STEP/BREP file it merges from its own folder. Every file is read once here; gmsh
    later imports these bytes, so what is keyed is what is meshed."""
    path = Path(path)
    source = str(path)
    kind = cad_kind(path)
    if kind != "geo":
        data = _read_regular(path, source, "the file", follow=True)
        _check_shape_data(data, kind, path, source)
        return CadSource(path, kind, path, data, (), {"cad_sha256": hashlib.sha256(data).hexdigest()})
    raw = _read_regular(path, source, "the .geo", follow=True, limit=MAX_GEO_BYTES)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"cage.cad = {source!r}: byte 0x{raw[exc.start]:02x} at offset {exc.start} is not "
                         f"UTF-8 text: not a cage .geo") from None
    name, line, groups = parse_cage_geo(text, source)
    shape_kind = CAD_SUFFIXES.get(Path(name).suffix.lower())
    if not _SAFE_NAME.fullmatch(name) or shape_kind not in ("step", "brep"):
        raise _geo_refusal(source, line, f"Merge {name!r} is not allowed (a STEP or BREP file name of "
                                         f"the .geo's own folder: letters, digits, space, _ . + -; no path)")
    shape = path.parent / name
    data = _read_regular(shape, source, "the merged file", follow=False)
    _check_shape_data(data, shape_kind, shape, source)
    return CadSource(path, shape_kind, shape, data, groups,
                     {"cad_sha256": hashlib.sha256(raw).hexdigest(),
                      "merged_sha256": {name: hashlib.sha256(data).hexdigest()}})


def _merged_line(src: CadSource) -> str:
    return f"the merged file {src.shape_file.name!r}" if src.shape_file != src.path else "the file"


@contextlib.contextmanager
def _captured_output():
    """OpenCASCADE's own messages (printed by the C++ library to the process's stdout and stderr,
    whatever gmsh's General.Terminal says) caught in a file while gmsh reads CAD: the refusal
    quotes them in its one line instead. Yields a function returning what was caught."""
    sys.stdout.flush()
    sys.stderr.flush()
    with tempfile.TemporaryFile() as log:
        saved = [os.dup(1), os.dup(2)]
        try:
            os.dup2(log.fileno(), 1)
            os.dup2(log.fileno(), 2)
            yield lambda: (log.seek(0), log.read().decode(errors="replace"))[1]
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)


def _occ_error(log: str) -> str:
    """The first error line OpenCASCADE printed, without its colour codes and stars."""
    for line in log.splitlines():
        s = re.sub(r"\x1b\[[0-9;]*m", "", line).strip(" *")
        if "ERR" in s or "rror" in s:
            return " ".join(s.split())[:160]
    return ""


_LENGTH_UNIT_ENTITY = re.compile(rb"(#\d+\s*=\s*)\((?:(?!;).)*?\bLENGTH_UNIT\s*\(\s*\)(?:(?!;).)*?\)\s*;", re.S)


def step_in_millimetres(data: bytes) -> tuple[bytes, int]:
    """A STEP file's text with every length-unit declaration (ISO 10303-41: the complex instance
    holding LENGTH_UNIT(), an SI_UNIT of any prefix or the inch's CONVERSION_BASED_UNIT) replaced
    by the millimetre, SI_UNIT(.MILLI.,.METRE.): OCC then takes the file's numbers as they are
    (its working unit is the mm), so a unit the user gives can override the declared one. Returns
    (text, number of declarations replaced)."""
    return _LENGTH_UNIT_ENTITY.subn(rb"\1( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );", data)


def _import(src: "CadSource", unit: str | None) -> tuple[list, str, float, list]:
    """Import the CAD source's STEP/BREP bytes into the current gmsh model and apply the .geo's
    named groups; return the volumes, the unit used, the factor from the model's numbers to
    metres and the notes to print (a unit given over the file's)."""
    import gmsh
    source = str(src.path)
    if unit is not None and unit not in UNITS:
        raise InputError(f"cad unit = {unit!r} is not known; allowed: {list(UNITS)}")
    data, notes = src.data, []
    if src.kind == "brep":
        if unit is None:
            what = "a BREP file" if src.shape_file == src.path else "a .geo merging a BREP file"
            raise InputError(f"cage.cad = {source!r}: {what} carries no unit; give it "
                             f"(--cad-unit / cage.cad_unit, one of {list(UNITS)})")
        used, scale = unit, UNITS[unit]
    else:
        declared = step_length_unit(data)
        if unit is None or unit == declared:
            # OCC converts the file's declared unit to its working unit, millimetres. gmsh's
            # Geometry.OCCTargetUnit would change that working unit for the rest of the process
            # (STEP written later included, even after gmsh.finalize()), so it is left alone and
            # the model scaled from mm here.
            used, scale = f"{declared or 'unknown'} (from the file)", 1e-3
        else:
            data, n = step_in_millimetres(data)
            used, scale = f"{unit} (given, over the file's {declared or 'unreadable'} unit)", UNITS[unit]
            notes.append(f"note: cad unit {unit!r} overrides the STEP file's declared length unit "
                         f"{declared or '(none we read)'}: its numbers are read as {unit}"
                         + ("" if n else " (the file declares no length unit)"))
    # scale, not dilated: OCC's dilation turns every face into a B-spline (10x slower to sample
    # and mesh); the faces are measured times `scale` and the mesh written scaled
    with tempfile.TemporaryDirectory(prefix="flexbearing-cad-") as folder:
        copy = Path(folder) / ("cage.step" if src.kind == "step" else "cage.brep")
        copy.write_bytes(data)
        with _captured_output() as caught:
            try:
                gmsh.model.occ.importShapes(str(copy))
                gmsh.model.occ.synchronize()
                failed = None
            except Exception as exc:          # gmsh raises Exception("Could not read file ...")
                failed = exc
            log = caught()
    if failed is not None:
        why = _occ_error(log) or str(failed).replace(str(copy), src.shape_file.name)
        raise InputError(f"cage.cad = {source!r}: gmsh cannot read {_merged_line(src)} as "
                         f"{'STEP' if src.kind == 'step' else 'BREP'} ({why})")
    vols = [t for d, t in gmsh.model.getEntities(3)]
    if len(vols) != 1:
        raise InputError(f"cage.cad = {source!r}: {len(vols)} solids in the file; a cage is one solid")
    _apply_groups(src)
    return vols, used, scale, notes


def _apply_groups(src: "CadSource") -> None:
    """The .geo's named groups on the imported model, each tag checked to be one of its faces
    (or volumes)."""
    import gmsh
    for g in src.groups:
        have = sorted(t for _, t in gmsh.model.getEntities(g.dim))
        missing = [t for t in g.tags if t not in set(have)]
        what = "face" if g.dim == 2 else "volume"
        if missing:
            raise InputError(f"cage.cad = {str(src.path)!r}: line {g.line}: group {g.name!r} names {what} "
                             f"{missing[0]}, which {src.shape_file.name!r} does not have (its {what}s: "
                             f"{have[0] if have else '-'} … {have[-1] if have else '-'})")
        tag = gmsh.model.addPhysicalGroup(g.dim, list(g.tags))
        gmsh.model.setPhysicalName(g.dim, tag, g.name)


_STEP_PREFIX = {"$": "m", ".MILLI.": "mm", ".CENTI.": "cm"}


def step_length_unit(data) -> str | None:
    """The length unit a STEP file declares (ISO 10303-41 SI_UNIT or the inch's
    CONVERSION_BASED_UNIT), as a key of UNITS; None when it declares none we know. data: the
    file's bytes (or its path)."""
    if not isinstance(data, (bytes, bytearray)):
        data = Path(data).read_bytes()
    text = data.decode("latin-1")
    m = re.search(r"LENGTH_UNIT\(\)\s*NAMED_UNIT\(\*\)\s*SI_UNIT\((\$|\.\w+\.)\s*,\s*\.METRE\.\)", text)
    if m:
        return _STEP_PREFIX.get(m.group(1))
    if re.search(r"CONVERSION_BASED_UNIT\s*\(\s*'INCH'", text, re.I):
        return "in"
    return None


_POCKET_NAME = re.compile(r"pockets?(?:[_ ]?(\d+))?$", re.I)
_GUIDE_NAMES = ("guide", "land")


@dataclass(frozen=True)
class NamedGroups:
    """The file's own names (module docstring): pocket groups (name, surface tags) in the order
    of their numbers, or one `pockets` group; the guide's surface tags; the names not used."""
    pockets: tuple = ()
    all_pockets: tuple = ()
    guide: tuple = ()
    guide_name: str = ""
    unused: tuple = ()


def named_groups() -> NamedGroups:
    """The physical surface groups of the current gmsh model read by the naming convention:
    `pocket_<n>` (or `pocket<n>`, `pocket <n>`, case-insensitive), `pockets`, `guide` / `land`."""
    import gmsh
    numbered, every, guide, guide_name, unused = [], [], [], "", []
    for dim, tag in gmsh.model.getPhysicalGroups(2):
        name = gmsh.model.getPhysicalName(dim, tag).strip()
        faces = tuple(int(s) for s in gmsh.model.getEntitiesForPhysicalGroup(dim, tag))
        m = _POCKET_NAME.match(name)
        if m and m.group(1) is not None:
            numbered.append((int(m.group(1)), name, faces))
        elif m:
            every.extend(faces)
        elif name.lower() in _GUIDE_NAMES:
            guide.extend(faces)
            guide_name = name
        else:
            unused.append(name)
    return NamedGroups(tuple((n, f) for _, n, f in sorted(numbered)), tuple(every), tuple(guide),
                       guide_name, tuple(unused))


def _named_pockets(named: NamedGroups, pockets: list, n_balls: int, source: str):
    """The pockets as the file names them, each face checked to be a pocket wall by its geometry
    (`pockets`: (face, azimuth, centre, shape, diameter, extra) of every face the geometry takes for a
    pocket wall); entries as `_group_pockets`'s, with the group's name."""
    wall = {s: (s, az, c, shape, dia, extra) for s, az, c, shape, dia, extra in pockets}
    groups = named.pockets or (("pockets", named.all_pockets),)
    for name, faces in groups:
        for s in faces:
            if s not in wall:
                raise InputError(f"cage.cad = {source!r}: named group {name!r}: face {s} is not a pocket "
                                 f"wall by its geometry (no sphere, no cylinder, cone or elliptic cylinder with a radial axis): the "
                                 f"names disagree with the geometry")
    if not named.pockets:
        return _group_pockets([wall[s] for s in named.all_pockets], n_balls, source, "named group 'pockets': ")
    if len(groups) != n_balls:
        raise InputError(f"cage.cad = {source!r}: {len(groups)} named pocket groups ({groups[0][0]} … "
                         f"{groups[-1][0]}), the bearing has bearing.n_balls = {n_balls}; one named "
                         f"pocket per ball")
    out = []
    for name, faces in groups:
        az = [wall[s][1] for s in faces]
        if max(abs(math.remainder(a - az[0], 2 * math.pi)) for a in az) > 1e-6:
            raise InputError(f"cage.cad = {source!r}: named group {name!r} holds faces of pockets at "
                             f"{sorted(round(math.degrees(a), 3) for a in az)}°: one pocket per group")
        out.append({"az": az[0], "faces": list(faces), "centres": [wall[s][2] for s in faces],
                    "shapes": {wall[s][3] for s in faces}, "diameters": [wall[s][4] for s in faces],
                    "extras": [wall[s][5] for s in faces], "name": name})
    return out


def _face_samples(tag: int, m: int = 5):
    """Points and unit normals of a face at m x m parametric points (projected onto the face)."""
    import gmsh
    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    u = np.linspace(lo[0], hi[0], m + 2)[1:-1]
    v = np.linspace(lo[1], hi[1], m + 2)[1:-1]
    uv = np.array([(a, b) for a in u for b in v]).ravel()
    P = np.asarray(gmsh.model.getValue(2, tag, uv)).reshape(-1, 3)
    N = np.asarray(gmsh.model.getNormal(tag, uv)).reshape(-1, 3)
    N /= np.linalg.norm(N, axis=1)[:, None]
    return P, N


def _classify(vol: int, n_balls: int, pitch_diameter: float, ball_diameter: float, guidance: str,
              source: str, scale: float):
    import gmsh
    # the bounding box only sizes the fit tolerance: OCC's boxes of transformed (B-spline) faces
    # are loose; positions come from the fitted faces
    xmin, ymin, zmin, xmax, ymax, zmax = (scale * v for v in gmsh.model.getBoundingBox(3, vol))
    tol = FIT_TOL * max(abs(ymin), abs(ymax), abs(zmin), abs(zmax))
    faces = [s for _, s in gmsh.model.getBoundary([(3, vol)], oriented=False)]
    fits = []
    for s in faces:
        P, N = _face_samples(s)
        P = P * scale
        fits.append((s, P, fit_face(P, N, tol)))
    xs_side = [f["x"] for _, _, f in fits if f["kind"] == "plane_x"]
    x_mid = 0.5 * (min(xs_side) + max(xs_side)) if len(xs_side) >= 2 else 0.5 * (xmin + xmax)
    shift = np.array([x_mid, 0.0, 0.0])
    ring, sides, pockets, other = [], [], [], []
    for s, P, f in fits:
        P = P - shift
        if f["kind"] == "plane_x":
            sides.append((s, f["x"] - x_mid))
        elif f["kind"] == "cylinder" and abs(abs(f["axis"][0]) - 1.0) < 1e-6 \
                and np.hypot(f["point"][1], f["point"][2]) < tol:
            ring.append((s, f["radius"], float(P[:, 0].min()), float(P[:, 0].max())))
        elif f["kind"] == "cylinder" and abs(f["axis"][0]) < 1e-6:
            a = f["axis"]
            # radial: the axis line passes through the bearing axis
            c = f["point"] - shift
            off = c - (c @ a) * a
            if np.linalg.norm(off[1:]) < tol:
                side = math.copysign(1.0, P.mean(axis=0) @ a)
                az = math.atan2(side * a[2], side * a[1])
                centre = np.array([off[0], 0.5 * pitch_diameter * math.cos(az), 0.5 * pitch_diameter * math.sin(az)])
                pockets.append((s, az, centre, "cylindrical", 2.0 * f["radius"], {}))
            else:
                other.append(s)
        elif f["kind"] == "sphere":
            c = f["centre"] - shift
            pockets.append((s, math.atan2(c[2], c[1]), c, "spherical", 2.0 * f["radius"], {}))
        elif f["kind"] == "cone" and abs(f["axis"][0]) < 1e-6:
            pocket = _cone_pocket(s, P, f, shift, pitch_diameter, tol, source)
            (pockets if pocket else other).append(pocket or s)
        elif f["kind"] == "elliptic_cylinder" and abs(f["axis"][0]) < 1e-6:
            pocket = _ellipse_pocket(s, P, f, shift, pitch_diameter, tol, source)
            (pockets if pocket else other).append(pocket or s)
        else:
            other.append(s)
    r_out = max((r for _, r, _, _ in ring), default=max(abs(ymin), abs(ymax), abs(zmin), abs(zmax)))
    if not 0.5 * pitch_diameter < r_out < 2.0 * pitch_diameter:
        raise InputError(f"cage.cad = {source!r}: the cage is {2 * r_out:.6g} m across, the bearing's "
                         f"pitch diameter {pitch_diameter:g} m; is the unit right (--cad-unit)?")
    xmin, xmax = (min(xs_side) - x_mid, max(xs_side) - x_mid) if len(xs_side) >= 2 else (xmin - x_mid, xmax - x_mid)
    return x_mid, (xmin, xmax), r_out, ring, sides, pockets, other


def _radial_side(P: np.ndarray, a: np.ndarray) -> tuple[float, np.ndarray]:
    """A radial axis a (normal to x) turned to point from the bearing axis towards the face's
    points: (azimuth from +y towards +z, the outward radial unit vector)."""
    side = math.copysign(1.0, P.mean(axis=0) @ a)
    er = side * np.array([0.0, a[1], a[2]])
    er /= np.linalg.norm(er)
    return math.atan2(er[2], er[1]), er


def _cone_pocket(s: int, P: np.ndarray, f: dict, shift: np.ndarray, pitch_diameter: float, tol: float,
                 source: str):
    """A cone whose axis is normal to the bearing axis as a conical pocket (CageGeometry's
    `pocket_shape = "conical"`): (face, azimuth, centre, "conical", Dp, {"cone_angle": β}), or
    None when it is no pocket (its axis passes farther from the bearing axis than its own radius
    there: a hole elsewhere, left as another face).

    The model's cone (CageGeometry.cone_radius) has its axis on the radial line through the
    pocket centre c (on the pitch circle) and radius ρ(s) = Dp/(2 cos β) + s tan β at s along the
    axis from c (+ outwards): tangent to the sphere of diameter Dp about c. The fitted cone (apex v,
    unit axis a into the cone, half-angle |β|) has ρ = h tan|β| at h = (q − v)·a from the apex, at
    the pitch point q = (x_axis, R_p e_r); so Dp = 2 ρ(q) cos β = 2 h sin|β|, and β > 0 (wider at
    the outside) when a points outwards (a·e_r > 0), < 0 when it points to the bore. A radial cone
    that does not hold the pitch point (h <= 0) is refused naming cage.pocket_shape."""
    v = f["apex"] - shift
    a = f["axis"]
    off = v - (v @ a) * a                               # the axis line's foot nearest the origin
    az, er = _radial_side(P - shift, a)
    rp = 0.5 * pitch_diameter
    q = np.array([off[0], rp * er[1], rp * er[2]])
    h = float((q - v) @ a)
    if np.linalg.norm(off[1:]) >= tol:
        if np.linalg.norm(off[1:]) < abs(h) * math.tan(f["half_angle"]):
            raise InputError(f"cage.cad = {source!r}: a conical face at {math.degrees(az):.3f}° has its axis "
                             f"{np.linalg.norm(off[1:]) * 1e3:.4f} mm off the bearing axis: cage.pocket_shape = "
                             f"'conical' is a cone about the radial line through the pocket centre (its apex on it)")
        return None
    if h <= 0:
        raise InputError(f"cage.cad = {source!r}: the conical face at {math.degrees(az):.3f}° has its apex "
                         f"{abs(h) * 1e3:.4f} mm beyond the pitch circle: cage.pocket_shape = 'conical' needs "
                         f"the cone open across the pitch circle")
    beta = math.copysign(f["half_angle"], a @ er)
    centre = np.array([off[0], q[1], q[2]])
    return (s, az, centre, "conical", 2.0 * h * math.sin(f["half_angle"]), {"cone_angle": beta})


def _ellipse_pocket(s: int, P: np.ndarray, f: dict, shift: np.ndarray, pitch_diameter: float, tol: float,
                    source: str):
    """An elliptic cylinder whose axis is normal to the bearing axis as an elliptical pocket
    (CageGeometry's `pocket_shape = "elliptical"`: a radial cylinder of elliptical section,
    diameter Dp along the bearing axis x, Dc in the direction of rotation t = x × e_r):
    (face, azimuth, centre, "elliptical", Dp, {"circumferential_diameter": Dc}), or None when
    its axis passes farther from the bearing axis than its minor semi-axis (a hole elsewhere).
    With the fitted semi-axes A >= B and the major's direction d, the section is turned by φ from
    the model's (d along x or along t); refused naming cage.pocket_circumferential_diameter when
    (A − B)|sin φ| (about the largest displacement of the wall) exceeds 10 tol."""
    c = f["point"] - shift
    a = f["axis"]
    off = c - (c @ a) * a
    az, er = _radial_side(P - shift, a)
    big, small = f["semi_axes"]
    if np.linalg.norm(off[1:]) >= tol:
        if np.linalg.norm(off[1:]) < small:
            raise InputError(f"cage.cad = {source!r}: an elliptic cylinder at {math.degrees(az):.3f}° has its axis "
                             f"{np.linalg.norm(off[1:]) * 1e3:.4f} mm off the bearing axis: cage.pocket_shape = "
                             f"'elliptical' is a cylinder about the radial line through the pocket centre")
        return None
    d = f["major"]
    t = np.cross([1.0, 0.0, 0.0], er)                   # direction of rotation at the pocket
    along_x = abs(d[0]) >= abs(d @ t)
    sin_phi = abs(d @ t) if along_x else abs(d[0])
    if (big - small) * sin_phi > 10 * tol:
        raise InputError(f"cage.cad = {source!r}: the elliptical pocket at {math.degrees(az):.3f}° has its axes "
                         f"turned {math.degrees(math.asin(min(1.0, sin_phi))):.3f}° from the bearing axis and the "
                         f"direction of rotation: the model's cage.pocket_diameter (axial) and "
                         f"cage.pocket_circumferential_diameter take them axial and circumferential")
    dx, dt = (2 * big, 2 * small) if along_x else (2 * small, 2 * big)
    rp = 0.5 * pitch_diameter
    centre = np.array([off[0], rp * er[1], rp * er[2]])
    return (s, az, centre, "elliptical", dx, {"circumferential_diameter": dt})


def _group_pockets(pockets, n_balls: int, source: str, named: str = ""):
    """Faces of one pocket share its azimuth (within 1e-6 rad): one entry per pocket."""
    out = []
    for s, az, c, shape, dia, extra in sorted(pockets, key=lambda t: t[1]):
        for p in out:
            if abs(math.remainder(az - p["az"], 2 * math.pi)) < 1e-6:
                p["faces"].append(s)
                p["centres"].append(c)
                p["shapes"].add(shape)
                p["diameters"].append(dia)
                p["extras"].append(extra)
                break
        else:
            out.append({"az": az, "faces": [s], "centres": [c], "shapes": {shape}, "diameters": [dia],
                        "extras": [extra]})
    if not out:
        raise InputError(f"cage.cad = {source!r}: no pocket found (no spherical face centred near the "
                         f"pitch circle, no cylindrical face with a radial axis, no cone or elliptic "
                         f"cylinder about a radial axis)")
    if len(out) != n_balls:
        raise InputError(f"cage.cad = {source!r}: {named}{len(out)} pockets found, the bearing has "
                         f"bearing.n_balls = {n_balls}; a cage needs one pocket per ball")
    return out


def read_cad_cage(path, n_balls: int, pitch_diameter: float, ball_diameter: float,
                  guidance: str = "outer", unit: str | None = None, material=None) -> CadCage:
    """Import, find and match the CAD cage in the current gmsh model (module docstring); the model
    is left turned so pocket 0 is at +y and centred on x = 0, with the faces classified."""
    import gmsh
    if guidance not in GUIDANCES:
        raise InputError(f"cage.guidance = {guidance!r} is not known; allowed: {list(GUIDANCES)}")
    src = path if isinstance(path, CadSource) else read_cad_source(path)
    source = str(src.path)
    vols, used, scale, notes = _import(src, unit)
    named = named_groups()
    # the mesh gets the model's own groups (cage_mesh); gmsh keeps a removed group's name, which
    # would then be refused to a new group of another tag: both go
    for dim, tag in gmsh.model.getPhysicalGroups():
        gmsh.model.removePhysicalName(gmsh.model.getPhysicalName(dim, tag))
    gmsh.model.removePhysicalGroups()
    x_mid, (xmin, xmax), r_out, ring, sides, pockets, other = _classify(
        vols[0], n_balls, pitch_diameter, ball_diameter, guidance, source, scale)
    found_by = {}
    if named.pockets or named.all_pockets:
        found = _named_pockets(named, pockets, n_balls, source)
        names = [p["name"] for p in found]
        found_by["pockets"] = (f"the file's named groups {names[0]} … {names[-1]}" if named.pockets
                               else "the file's named group 'pockets'")
        taken = {s for p in found for s in p["faces"]}
        other = other + [s for s, *_ in pockets if s not in taken]
    else:
        found = _group_pockets(pockets, n_balls, source)
        found_by["pockets"] = "geometry (spheres centred near the pitch circle, cylinders with a radial axis)"
    # turn (and centre) the solid so pocket 0 is at +y and the mid-plane at x = 0
    turn = -min(found, key=lambda p: abs(p["az"]))["az"]
    occ = gmsh.model.occ
    occ.translate([(3, vols[0])], -x_mid / scale, 0.0, 0.0)     # positions above are already centred
    occ.rotate([(3, vols[0])], 0, 0, 0, 1, 0, 0, turn)
    occ.synchronize()
    z = n_balls
    found.sort(key=lambda p: (p["az"] + turn) % (2 * math.pi))
    diam = np.array([d for p in found for d in p["diameters"]])
    shapes = set().union(*(p["shapes"] for p in found))
    if len(shapes) != 1:
        raise InputError(f"cage.cad = {source!r}: pockets of mixed shapes {sorted(shapes)}; one shape per cage")
    shape = shapes.pop()
    if shape in ("conical", "elliptical") and not (named.pockets or named.all_pockets):
        found_by["pockets"] = ("geometry (cones about a radial axis)" if shape == "conical"
                               else "geometry (elliptic cylinders about a radial axis)")
    dp = float(diam.mean())
    if np.ptp(diam) > 1e-3 * dp:
        raise InputError(f"cage.cad = {source!r}: pocket diameters differ ({diam.min() * 1e3:.4f} to "
                         f"{diam.max() * 1e3:.4f} mm); the model takes one pocket diameter")
    if dp <= ball_diameter:
        raise InputError(f"cage.cad = {source!r}: pocket diameter {dp * 1e3:.4f} mm is not larger than "
                         f"the ball, bearing.ball_diameter = {ball_diameter * 1e3:.4f} mm")
    cp = 0.5 * (dp - ball_diameter)
    extras = _shape_fields(shape, found, dp, source)
    pockets_out = []
    c_turn = (math.cos(turn), math.sin(turn))
    for k, p in enumerate(found):
        az = (p["az"] + turn) % (2 * math.pi)
        if abs(math.remainder(az - 2 * math.pi * k / z, 2 * math.pi)) * 0.5 * pitch_diameter > 0.1 * cp:
            raise InputError(f"cage.cad = {source!r}: pocket {k}{_group_of(p)} at {math.degrees(az):.4f}°, not at "
                             f"{360.0 * k / z:.4f}° (equal spacing of {z} pockets within 0.1·Cp of arc)")
        c = np.mean(p["centres"], axis=0)
        c = np.array([c[0], c[1] * c_turn[0] - c[2] * c_turn[1], c[1] * c_turn[1] + c[2] * c_turn[0]])
        rc = math.hypot(c[1], c[2])
        if abs(rc - 0.5 * pitch_diameter) > 0.1 * cp or abs(c[0]) > 0.1 * cp:
            raise InputError(f"cage.cad = {source!r}: pocket {k}{_group_of(p)} is centred at radius {rc * 1e3:.4f} mm, "
                             f"x {c[0] * 1e3:+.4f} mm: off the pitch circle (radius "
                             f"{0.5 * pitch_diameter * 1e3:.4f} mm, x 0) by more than 0.1·Cp = "
                             f"{0.1 * cp * 1e6:.1f} µm")
        pockets_out.append(FoundPocket(az, tuple(c), shape, float(np.mean(p["diameters"])), tuple(p["faces"]),
                                       float(np.mean([e.get("cone_angle", 0.0) for e in p["extras"]])),
                                       float(np.mean([e.get("circumferential_diameter", 0.0) for e in p["extras"]]))))
    if not ring:
        raise InputError(f"cage.cad = {source!r}: no cylindrical face about the bearing axis: not a ring cage")
    # ring cylinders: the face radii clustered within 2·FIT_TOL, each cluster's mean
    clusters: list[list] = []
    for t in sorted(ring, key=lambda t: t[1]):
        if clusters and t[1] - clusters[-1][-1][1] < 2 * FIT_TOL * r_out:
            clusters[-1].append(t)
        else:
            clusters.append([t])
    radii = [float(np.mean([t[1] for t in c])) for c in clusters]
    cyl = tuple((r, min(t[2] for t in c), max(t[3] for t in c), len(c)) for r, c in zip(radii, clusters))
    r_o, r_i = radii[-1], radii[0]
    width = xmax - xmin                 # between the side planes (the box only without them)
    groups: dict[str, list[int]] = {}
    for k, p in enumerate(pockets_out):
        groups[CM.pocket_name(k)] = list(p.faces)
    for s, x in sides:
        groups.setdefault("side_left" if x < 0 else "side_right", []).append(s)
    guide_r = None if guidance == "balls" else (r_o if guidance == "outer" else r_i)
    named_guide = _named_guide(named, ring, guidance, pitch_diameter, source)
    if guidance == "balls":
        found_by["guide"] = "none needed (guidance balls" + (f"; the file's group {named.guide_name!r} not used)"
                                                             if named.guide else ")")
    elif named_guide:
        found_by["guide"] = f"the file's named group {named.guide_name!r}"
    else:
        found_by["guide"] = f"geometry (the ring cylinder at the {'largest' if guidance == 'outer' else 'smallest'} radius)"
    if named.unused:                           # said, so a misspelt name is not silently ignored
        found_by["unused"] = ", ".join(named.unused)
    guide = []
    for s, r, x0, x1 in ring:
        if (s in named_guide) if named_guide else (guide_r is not None and abs(r - guide_r) < 2 * FIT_TOL * r_out):
            guide.append(s)
            groups.setdefault("guide", []).append(s)
        elif abs(r - r_o) < 2 * FIT_TOL * r_out:
            groups.setdefault("outside", []).append(s)
        elif abs(r - r_i) < 2 * FIT_TOL * r_out:
            groups.setdefault("bore", []).append(s)
        else:
            groups.setdefault("other", []).append(s)
    groups.setdefault("other", []).extend(other)
    if not groups["other"]:
        del groups["other"]
    if guidance != "balls" and not guide:
        raise InputError(f"cage.cad = {source!r}: no land for cage.guidance = {guidance!r}")
    # the land(s): axial extent of the guide faces; two separate bands = two lands with a relief
    land_width, relief = 0.5 * width, 0.0
    if guidance == "outer":
        fs = [t for t in ring if t[0] in guide]
        xs = sorted((t[2], t[3]) for t in fs)
        covered = [xs[0]]
        for a, b in xs[1:]:
            if a <= covered[-1][1] + FIT_TOL * r_out:
                covered[-1] = (covered[-1][0], max(covered[-1][1], b))
            else:
                covered.append((a, b))
        if len(covered) == 2 and len(radii) > 2:
            land_width = 0.5 * sum(b - a for a, b in covered)
            relief = r_o - max(r for r in radii[:-1] if r > 0.5 * pitch_diameter) \
                if any(r > 0.5 * pitch_diameter for r in radii[:-1]) else 0.0
    geometry = PAPER_CAGE.with_(
        outside_diameter=2 * r_o, bore_diameter=2 * r_i, width=width, n_pockets=z, pocket_diameter=dp,
        land_width=land_width, relief_depth=relief, chamfer=0.0, bore_chamfer=None,
        ball_diameter=ball_diameter, guidance=guidance, pocket_shape=shape,
        pocket_centre_diameter=pitch_diameter if shape in ("spherical", "conical") else PAPER_CAGE.pocket_centre_diameter,
        **extras,
        **({"material": material} if material is not None else {}))
    _check_shape_fields(geometry, source)
    return CadCage(geometry=geometry, pockets=tuple(pockets_out), ring_cylinders=tuple(cyl),
                   guide_faces=tuple(guide), turned_by=turn, unit=used, source=source, scale=scale,
                   groups={k: list(v) for k, v in groups.items()}, found_by=found_by, notes=tuple(notes))


def _shape_fields(shape: str, found: list, dp: float, source: str) -> dict:
    """The CageGeometry fields of a conical or an elliptical cage from its pockets (one value for
    all, as the pocket diameter), refused in one line naming the field when the model cannot take
    them: the half-angle within ±MAX_CONE_ANGLE; the circumferential diameter at least the axial."""
    from .cage_geometry import MAX_CONE_ANGLE
    if shape == "conical":
        beta = np.array([e["cone_angle"] for p in found for e in p["extras"]])
        if np.ptp(beta) > 1e-6:
            raise InputError(f"cage.cad = {source!r}: cone half-angles differ ({math.degrees(beta.min()):+.4f}° to "
                             f"{math.degrees(beta.max()):+.4f}°); the model takes one cage.pocket_cone_angle")
        b = float(beta.mean())
        if abs(b) > MAX_CONE_ANGLE:
            raise InputError(f"cage.cad = {source!r}: cage.pocket_cone_angle = {math.degrees(b):+.3f}° found, "
                             f"allowed: within ±{math.degrees(MAX_CONE_ANGLE):.0f}°")
        return {"pocket_cone_angle": b}
    if shape == "elliptical":
        dc = np.array([e["circumferential_diameter"] for p in found for e in p["extras"]])
        d = float(dc.mean())
        if np.ptp(dc) > 1e-3 * d:
            raise InputError(f"cage.cad = {source!r}: pocket circumferential diameters differ ({dc.min() * 1e3:.4f} "
                             f"to {dc.max() * 1e3:.4f} mm); the model takes one cage.pocket_circumferential_diameter")
        if d < dp:
            raise InputError(f"cage.cad = {source!r}: cage.pocket_circumferential_diameter = {d * 1e3:.4f} mm found, "
                             f"smaller than the axial cage.pocket_diameter = {dp * 1e3:.4f} mm; the model's "
                             f"elliptical pocket is at least as long in the direction of rotation")
        return {"pocket_circumferential_diameter": d}
    return {}


def _check_shape_fields(geometry: CageGeometry, source: str) -> None:
    """The model's own limits on a conical or elliptical pocket (CageGeometry.validate: the cone's
    half-angle and wide end, the ellipse between the axial diameter and what the ball's curvature
    and the neighbours allow), applied to the found cage: refused in validate's line naming the
    field. Other limits are left to the bearing's check, as for cylindrical and spherical pockets."""
    fields = {"conical": "cage.pocket_cone_angle", "elliptical": "cage.pocket_circumferential_diameter"}
    name = fields.get(geometry.pocket_shape)
    if name is None:
        return
    try:
        geometry.validate()
    except InputError as e:
        if str(e).startswith(name):
            raise InputError(f"cage.cad = {source!r}: {e} (the {geometry.pocket_shape} pocket found in the file)") from None


def _group_of(pocket: dict) -> str:
    return f" (named group {pocket['name']!r})" if pocket.get("name") else ""


def _named_guide(named: NamedGroups, ring: list, guidance: str, pitch_diameter: float, source: str) -> set:
    """The guide faces the file names, each checked to be a cylinder about the bearing axis on the
    side of the pitch circle the guidance needs (outside for "outer", the bore for "inner")."""
    if not named.guide or guidance == "balls":
        return set()
    radius = {s: r for s, r, _, _ in ring}
    for s in named.guide:
        if s not in radius:
            raise InputError(f"cage.cad = {source!r}: named group {named.guide_name!r}: face {s} is not a "
                             f"cylinder about the bearing axis: the names disagree with the geometry")
        outside = radius[s] > 0.5 * pitch_diameter
        if outside != (guidance == "outer"):
            raise InputError(f"cage.cad = {source!r}: named group {named.guide_name!r}: face {s} at radius "
                             f"{radius[s] * 1e3:.4f} mm is {'outside' if outside else 'inside'} the pitch "
                             f"circle; cage.guidance = {guidance!r} needs the "
                             f"{'outside' if guidance == 'outer' else 'bore'}")
    return set(named.guide)


def build_cad_cage_mesh(path, out, n_balls: int, pitch_diameter: float, ball_diameter: float,
                        guidance: str = "outer", unit: str | None = None,
                        size: float = CM.DEFAULT_MESH_SIZE, pocket_size: float | None = CM.DEFAULT_POCKET_SIZE,
                        order: int = CM.DEFAULT_ORDER, material=None) -> CadCage:
    """Read the CAD cage (`read_cad_cage`; path: a file or a `CadSource` already read), mesh it
    with the parametric cage's groups and sizes (flexbearing.mesh.cage_mesh.tag_and_mesh), check
    and repair its elements, write `out` (.msh, whole or not at all) and its quality sidecar (with
    the mesh's digest: flexbearing.mesh.cage_mesh.write_quality); return what was found."""
    import gmsh
    out = Path(out)
    src = path if isinstance(path, CadSource) else read_cad_source(path)      # before gmsh runs
    for given in {src.path, src.shape_file}:
        if out.resolve() == given.resolve():
            raise InputError(f"mesh output {str(out)!r} is the CAD input {str(given)!r}")
    from flexbearing.common.fe_stack import gmsh_initialize
    gmsh_initialize(gmsh)      # gmsh >= 4.9 off the main thread: fe_stack
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("cad_cage")
        cad = read_cad_cage(src, n_balls, pitch_diameter, ball_diameter, guidance, unit, material)
        vols = [t for _, t in gmsh.model.getEntities(3)]
        k = cad.scale
        CM.tag_and_mesh(vols, cad.groups, n_balls, size / k, order, None if pocket_size is None else pocket_size / k)
        report = CM._validate_and_repair()
        report["repair"]["max_node_shift_m"] *= k              # measured in the model's unit
        previous = gmsh.option.getNumber("Mesh.ScalingFactor")
        gmsh.option.setNumber("Mesh.ScalingFactor", k)         # the file in metres
        try:
            CM._write(out)
        finally:
            gmsh.option.setNumber("Mesh.ScalingFactor", previous)
    finally:
        gmsh.finalize()
    CM.write_quality(out, report)
    return cad



# ---------------------------------------------------------------- cached: what a scene's cage.cad needs
CAD_RECORD_VERSION = 2          # 2: the record's own digest; keys by every file the geometry reads


def _cad_key(src: CadSource, n_balls: int, pitch_diameter: float, ball_diameter: float, guidance: str,
             unit: str | None, material) -> dict:
    """Every input of `read_cad_cage`: every file the geometry reads by its content (sha256: the
    .geo, and the STEP/BREP it merges), not its name; the bearing; the unit; the fit tolerance."""
    return {"kind": "cad_cage", **src.digests, "n_balls": int(n_balls),
            "pitch_diameter": float(pitch_diameter), "ball_diameter": float(ball_diameter),
            "guidance": guidance, "unit": unit, "material": asdict(material), "fit_tol": FIT_TOL,
            "record_version": CAD_RECORD_VERSION}


def cad_geometry_from_dict(d: dict) -> CageGeometry:
    """The CageGeometry of a dict (dataclasses.asdict's, as a CAD record stores it)."""
    d = dict(d)
    d["material"] = Material(**d["material"])
    return CageGeometry(**d)


_geometry_from_dict = cad_geometry_from_dict


def cad_record_digest(rec: dict) -> str:
    """sha256 of a CAD cache record's canonical JSON (key, geometry, report), its "sha256" left out."""
    body = {k: v for k, v in rec.items() if k != "sha256"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def read_cad_record(store: Path, key: dict | None = None):
    """(CageGeometry, report lines, key) of a CAD cache record, or None when it is missing,
    truncated, edited (its digest), not of `key`, or its geometry is not a valid cage: the caller
    then finds the cage again and writes the record anew."""
    try:
        if store.is_symlink() or not store.is_file():
            return None
        rec = json.loads(store.read_text(encoding="utf-8"))
        if not isinstance(rec, dict) or rec.get("sha256") != cad_record_digest(rec):
            return None
        if key is not None and rec.get("key") != key:
            return None
        geometry = _geometry_from_dict(rec["geometry"])
        geometry.validate()
        report = [str(x) for x in rec["report"]]
        return geometry, report, rec["key"]
    except (OSError, ValueError, TypeError, KeyError, AttributeError, InputError):
        return None


def cad_record_path(key: dict) -> Path:
    return cache_dir() / "meshes" / f"{content_hash(key)}.cad.json"


def cad_cage_geometry(path, n_balls: int, pitch_diameter: float, ball_diameter: float,
                      guidance: str = "outer", unit: str | None = None, material=None):
    """(equivalent CageGeometry, report lines, key) of a CAD cage, cached by the content of every
    file it reads and the bearing (`_cad_key`): a scene reads it without gmsh once it has been
    found. The input is read as data first (`read_cad_source`: a .geo is parsed, never run);
    a damaged or edited cache record is found again and rewritten."""
    import gmsh
    material = material or PAPER_CAGE.material
    src = path if isinstance(path, CadSource) else read_cad_source(path)
    key = _cad_key(src, n_balls, pitch_diameter, ball_diameter, guidance, unit, material)
    store = cad_record_path(key)
    cached = read_cad_record(store, key)
    if cached is not None:
        return cached
    from flexbearing.common.fe_stack import gmsh_initialize
    gmsh_initialize(gmsh)      # gmsh >= 4.9 off the main thread: fe_stack
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        cad = read_cad_cage(src, n_balls, pitch_diameter, ball_diameter, guidance, unit, material)
    finally:
        gmsh.finalize()
    rec = {"key": key, "geometry": asdict(cad.geometry), "report": cad.report_lines(pitch_diameter, ball_diameter)}
    rec["sha256"] = cad_record_digest(rec)
    write_text_atomic(store, json.dumps(rec, indent=1))
    return cad.geometry, rec["report"], key


def cached_cad_cage_mesh(path, n_balls: int, pitch_diameter: float, ball_diameter: float,
                         guidance: str = "outer", unit: str | None = None, material=None,
                         size: float = CM.DEFAULT_MESH_SIZE, pocket_size: float | None = CM.DEFAULT_POCKET_SIZE,
                         order: int = CM.DEFAULT_ORDER, expect_key: dict | None = None) -> tuple[Path, dict]:
    """The CAD cage's mesh from the cache (keyed by the content of every file it reads, the
    bearing and the mesh sizes), built once (`build_cad_cage_mesh`) and used only while its digest
    matches (flexbearing.mesh.cage_mesh.verified_mesh; otherwise built again); returns (path, key).
    expect_key: the CAD key the scene was validated with; files changed since are refused."""
    material = material or PAPER_CAGE.material
    src = path if isinstance(path, CadSource) else read_cad_source(path)
    cad_key = _cad_key(src, n_balls, pitch_diameter, ball_diameter, guidance, unit, material)
    if expect_key is not None and cad_key != expect_key:
        raise InputError(f"cage.cad = {str(src.path)!r}: the file changed since the scene was read "
                         f"(its content digest differs): read the scene again")
    out, key = cad_mesh_cache_path(cad_key, size, pocket_size, order)
    if not CM.verified_mesh(out):
        build_cad_cage_mesh(src, out, n_balls, pitch_diameter, ball_diameter, guidance, unit, size,
                            pocket_size, order, material)
    return out, key


def cad_mesh_cache_path(cad_key: dict, size: float, pocket_size: float | None, order: int) -> tuple[Path, dict]:
    """(path, key) of the cached mesh of a CAD cage of key `cad_key` (`_cad_key`) at these sizes."""
    key = {**cad_key, "size": float(size), "pocket_size": None if pocket_size is None else float(pocket_size),
           "order": int(order), "mesh_version": CM.MESH_VERSION}
    return cache_dir() / "meshes" / f"{content_hash(key)}.msh", key
