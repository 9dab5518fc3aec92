"""Batch jobs: one mapping of the CLI's options, checked and named before anything runs.

A job is checked in the driver (:func:`parse_job`), so a typo fails as one clear error
row before any worker starts, and the job that travels to a worker holds only strings,
numbers and tuples: it pickles for any executor (process pool, Dask, Ray).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

from .._checks import check_alpha, check_positive_int, check_vector
from ..errors import ArgumentError
from ..sinks.files import writers
from ..sources.drawing import is_drawing, load_drawing
from ..sources.solids import sections

__all__ = ["Job", "parse_job", "wants_graded", "numbered", "plane_sections", "OPTIONS", "AXES"]

AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
_PLANE_OPTIONS = ("axis", "plane_normal", "plane_origin", "at", "slices")
#: The keys a job may have: the CLI's options, with ``_`` for ``-``.
OPTIONS = ("input", "output", *_PLANE_OPTIONS, "layer", "alpha", "graded", "conforming", "seed",
           "max_samples")
_TRUE, _FALSE = ("true", "yes", "1"), ("false", "no", "0")


@dataclass(frozen=True)
class Job:
    """One checked job: its input, the files it writes and the options that make them.

    Attributes
    ----------
    index : int
        Position in the batch (0-based), the order of ``results.jsonl``.
    input : str
        Absolute path of the mesh file or drawing (SVG, DXF).
    output : str
        Absolute path of the output; with several sections the files are
        ``STEM_000.SUFFIX``, ``STEM_001.SUFFIX``... (see ``outputs``).
    outputs : tuple of str
        Every mesh file the job writes, in the order of its planes.
    options : tuple of (str, value) pairs
        The options that determine the meshes (plane, alpha, graded, conforming, seed,
        budget), in
        a fixed order; a rerun with other options is not skipped.
    run : str
        Which :func:`~pds_plugin.mesh_batch` call sent it (set there): each run's tasks
        differ, so an executor that caches results by their arguments (Dask's pure
        tasks) runs a rerun's job again instead of returning the old row.
    """

    index: int
    input: str
    output: str
    outputs: tuple
    options: tuple
    run: str = ""

    @property
    def settings(self) -> dict:
        """The options as a dict (JSON-ready)."""
        return {name: list(value) if isinstance(value, tuple) else value
                for name, value in self.options}

    @property
    def record(self) -> Path:
        """The JSON file beside the output that proves the job done (see :mod:`.worker`)."""
        return Path(f"{self.output}.json")

    def regions(self) -> list:
        """Load the input and cut it: the job's sections as :class:`~pds_plugin.Region`\\ s."""
        o = self.settings
        if is_drawing(self.input):
            return [load_drawing(self.input, **({"layers": o["layer"]} if o["layer"] else {}))]
        return plane_sections(self.input, AXES.get(o["axis"], o["plane_normal"]),
                              plane_origin=o["plane_origin"], at=o["at"], slices=o["slices"])


def plane_sections(solid, normal, *, plane_origin=None, at=None, slices=None,
                   on_face=None, tolerance=None) -> list:
    """The sections of ``solid`` the command line's plane options ask for.

    ``slices`` planes across the solid; else the planes through ``plane_origin`` (the
    world origin by default) moved by each offset of ``at`` along the unit normal; with
    neither ``at`` nor ``plane_origin``, the middle of the solid.

    Parameters
    ----------
    solid : str, os.PathLike, trimesh.Trimesh or manifold3d.Manifold
    normal : (3,) array_like
    plane_origin : (3,) array_like, optional
    at : sequence of float, optional
    slices : int, optional
    on_face : {"above", "below"}, optional
        For planes given by ``at`` or ``plane_origin`` that lie on faces of the solid
        (refused by default); the automatic planes move off faces by themselves.
    tolerance : float, optional
        As in :func:`pds_plugin.section` (default: estimated from the mesh).

    Returns
    -------
    list of Region

    Raises
    ------
    SectionError, SourceError, ArgumentError, OSError
        As :func:`pds_plugin.sections`.

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box(extents=(2, 2, 2))
    >>> [float(r.frame[2, 3]) for r in plane_sections(box, AXES["z"], at=[0.5])]
    [0.5]
    >>> [float(r.frame[2, 3]) for r in plane_sections(box, AXES["z"])]
    [0.0]
    """
    if slices is not None:
        return sections(solid, normal, count=slices, tolerance=tolerance)
    if at is None and plane_origin is None:
        return sections(solid, normal, count=1, tolerance=tolerance)
    return sections(solid, normal, offsets=at or [0.0], plane_origin=plane_origin,
                    on_face=on_face, tolerance=tolerance)


def parse_job(mapping, index: int, out_dir, base_dir=".") -> Job:
    """Check one job mapping and resolve its paths.

    Values may be typed (numbers, lists, booleans) or text, as in a CSV manifest
    (``"0,0,1"``, ``"auto"``, ``"true"``); empty values count as absent.

    Parameters
    ----------
    mapping : Mapping
        The job: keys from :data:`OPTIONS`; ``input`` is required. As for ``pds-mesh``,
        ``alpha`` defaults to ``"auto"``, which makes a graded mesh unless ``graded`` is
        false (:func:`wants_graded`).
    index : int
        Its position in the batch.
    out_dir : str or os.PathLike
        Relative outputs are put there.
    base_dir : str or os.PathLike
        Relative inputs are read from there (the manifest's folder).

    Returns
    -------
    Job

    Raises
    ------
    ArgumentError
        Naming the option that is wrong and what to write instead.

    Examples
    --------
    >>> job = parse_job({"input": "part.stl", "axis": "z", "at": "0.5", "alpha": "auto"},
    ...                 0, "/out", base_dir="/parts")
    >>> job.input, job.output, job.settings["at"]
    ('/parts/part.stl', '/out/part_z0.5.ply', [0.5])
    >>> parse_job({"input": "part.stl", "alpha": 0.1, "axes": "z"}, 3, "/out")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentError: unknown option 'axes'; a job has input, output, axis, plane_normal, plane_origin, at, slices, layer, alpha, graded, conforming, seed, max_samples
    """
    if not hasattr(mapping, "items"):
        raise ArgumentError(f"a job is a mapping of options (a JSON object), got "
                            f"{type(mapping).__name__}")
    given = {str(key).strip(): value for key, value in mapping.items()
             if not (value is None or (isinstance(value, str) and not value.strip()))}
    unknown = sorted(set(given) - set(OPTIONS))
    if unknown:
        raise ArgumentError(f"unknown option {unknown[0]!r}; a job has {', '.join(OPTIONS)}")
    if "input" not in given:
        raise ArgumentError("the job has no input: give the mesh file or drawing to mesh")
    source = Path(base_dir, str(given["input"])).absolute()
    settings = {name: _PARSERS[name](given[name], name) if name in given else None
                for name in OPTIONS[2:]}
    settings["alpha"] = "auto" if settings["alpha"] is None else settings["alpha"]
    settings["graded"] = wants_graded(settings["alpha"], settings["graded"],
                                      settings["conforming"])
    if settings["graded"] and settings["conforming"] is False:
        raise ArgumentError("graded meshes are always conforming; drop conforming: false "
                            "or graded")
    settings["conforming"] = settings["conforming"] is not False     # the default: True
    settings["seed"] = settings["seed"] or 0
    _check_plane(settings, source)
    count = settings["slices"] or len(settings["at"] or [0.0])
    output = Path(out_dir, str(given["output"]) if "output" in given
                  else _derived_name(source, settings)).absolute()
    if output.suffix.lower() not in writers():
        raise ArgumentError(f"cannot write {output.name}: the output suffix must be one "
                            f"of {', '.join(writers())}")
    outputs = tuple(map(str, numbered(output, count)))
    if str(source) in outputs:
        raise ArgumentError(f"the output {output} would overwrite the input; choose another")
    options = tuple((name, tuple(v) if isinstance(v, list) else v)
                    for name, v in settings.items())
    return Job(index, str(source), str(output), outputs, options)


def wants_graded(alpha, graded: bool | None = None, conforming: bool | None = True) -> bool:
    """Whether a mesh of ``pds-mesh`` or of a batch job is graded: ``graded`` when given,
    else graded exactly for ``alpha="auto"`` on a conforming mesh (graded meshes are
    always conforming; ``conforming`` None means the default, True). The one rule of the
    command line (``--graded``, ``--uniform``) and of batch jobs (``graded``).

    Parameters
    ----------
    alpha : float or "auto"
    graded : bool, optional
        Asked for (True) or refused (False); None when not said.
    conforming : bool, optional

    Returns
    -------
    bool

    Examples
    --------
    >>> wants_graded("auto"), wants_graded("auto", False), wants_graded(0.2), wants_graded(0.2, True)
    (True, False, False, True)
    >>> wants_graded("auto", conforming=False)
    False
    """
    if graded is not None:
        return bool(graded)
    return alpha == "auto" and conforming is not False


def numbered(path: Path, count: int) -> list[Path]:
    """``path`` itself for one section, else ``stem_000.suffix``, ``stem_001.suffix``...

    Parameters
    ----------
    path : pathlib.Path
    count : int
        The number of sections.

    Returns
    -------
    list of pathlib.Path
        Zero-padded to 3 digits, more when there are more sections.

    Examples
    --------
    >>> [p.name for p in numbered(Path("cut.ply"), 2)]
    ['cut_000.ply', 'cut_001.ply']
    """
    if count == 1:
        return [path]
    width = max(3, len(str(count - 1)))
    return [path.with_name(f"{path.stem}_{i:0{width}d}{path.suffix}") for i in range(count)]


# --- option values -------------------------------------------------------------------

def _numbers(value, name) -> list[float]:
    """Numbers given as a list, one number, or text like ``"0.5,1"``."""
    items = value.split(",") if isinstance(value, str) else \
        (value if isinstance(value, (list, tuple)) else [value])
    try:
        if not items or any(isinstance(item, bool) for item in items):
            raise ValueError
        return check_vector([float(item) for item in items], name, size=len(items)).tolist()
    except (TypeError, ValueError):
        raise ArgumentError(f"{name} must be finite numbers (a list, or text like '0.5,1'), "
                            f"got {value!r}") from None


def _point(value, name) -> list[float]:
    point = _numbers(value, name)
    if len(point) != 3:
        raise ArgumentError(f"{name} must be three numbers x, y, z, got {value!r}")
    if name == "plane_normal" and not any(point):
        raise ArgumentError(f"{name} is the zero vector; give the direction the plane "
                            f"faces, e.g. [0, 0, 1]")
    return point


def _integer(value, name) -> int:
    """An integer given as a number or text; positive but for the seed."""
    try:
        number = int(value) if isinstance(value, str) else value
    except ValueError:
        number = None
    if isinstance(number, float) and number.is_integer():
        number = int(number)
    if name == "seed" and isinstance(number, int) and not isinstance(number, bool):
        return number
    if name == "seed" or number is None:
        raise ArgumentError(f"{name} must be an integer, got {value!r}")
    return check_positive_int(number, name)


def _alpha(value, name):
    if isinstance(value, str) and value.strip() == "auto":
        return "auto"
    if isinstance(value, (list, tuple, bool)):
        raise ArgumentError(f"alpha must be a positive number or 'auto', got {value!r}")
    try:
        return check_alpha(value)
    except ValueError:
        raise ArgumentError(f"alpha must be a positive number or 'auto', got {value!r}") from None


def _boolean(value, name) -> bool:
    if isinstance(value, bool):
        return value
    if str(value).strip().lower() in _TRUE + _FALSE:
        return str(value).strip().lower() in _TRUE
    raise ArgumentError(f"{name} must be true or false, got {value!r}")


def _names(value, name) -> list[str]:
    """Names given as a list or as text like ``"OUTLINE,HOLES"``."""
    names = value.split(",") if isinstance(value, str) else value
    if not isinstance(names, (list, tuple)) or not all(isinstance(n, str) and n.strip()
                                                       for n in names):
        raise ArgumentError(f"{name} must be names (a list, or text like 'OUTLINE,HOLES'), "
                            f"got {value!r}")
    return [n.strip() for n in names]


def _axis(value, name) -> str:
    if value not in AXES:
        raise ArgumentError(f"{name} must be one of {', '.join(AXES)}, got {value!r}")
    return value


_PARSERS = {"layer": _names, "axis": _axis, "plane_normal": _point, "plane_origin": _point, "at": _numbers,
            "slices": _integer, "alpha": _alpha, "graded": _boolean, "conforming": _boolean,
            "seed": _integer,
            "max_samples": _integer}


def _check_plane(settings: dict, source: Path) -> None:
    """The plane options make sense for the input's kind (the CLI's rules)."""
    given = [name for name in _PLANE_OPTIONS if settings[name] is not None]
    if settings["layer"] is not None and source.suffix.lower() != ".dxf":
        raise ArgumentError(f"layer selects layers of a DXF drawing; {source.name} is not one")
    if is_drawing(source):
        if given:
            raise ArgumentError(f"{source.name} is a {source.suffix[1:].upper()} drawing, "
                                f"which is already planar: drop {given[0]}")
        return
    if settings["axis"] is not None and settings["plane_normal"] is not None:
        raise ArgumentError("give either axis or plane_normal, not both")
    if settings["at"] is not None and settings["slices"] is not None:
        raise ArgumentError("give either at (offsets) or slices (a count), not both")
    if settings["axis"] is None and settings["plane_normal"] is None:
        raise ArgumentError(f"{source.name} is a solid: say where to cut it with axis or "
                         f"plane_normal (and at, plane_origin or slices)")
    if settings["slices"] is not None and settings["plane_origin"] is not None:
        raise ArgumentError("slices spreads the planes across the whole solid: drop "
                         "plane_origin, or give at offsets from it instead")


def _derived_name(source: Path, settings: dict) -> str:
    """``part.ply`` (a drawing), ``part_z0.5.ply``, ``part_z_middle.ply``, ``part_z_slices10.ply``;
    any other plane: ``part_plane-HASH.ply`` from the plane options."""
    axis, at, slices = settings["axis"], settings["at"], settings["slices"]
    if is_drawing(source):
        label = ""
    elif axis is not None and settings["plane_origin"] is None:
        if slices is not None:
            label = f"_{axis}_slices{slices}"
        elif at is None:
            label = f"_{axis}_middle"
        elif len(at) == 1:
            label = f"_{axis}{at[0]!r}"
        else:
            label = f"_{axis}_{len(at)}planes-{_digest(at)}"
    else:
        label = f"_plane-{_digest({name: settings[name] for name in _PLANE_OPTIONS})}"
    return f"{source.stem}{label}.ply"


def _digest(value) -> str:
    return hashlib.sha256(json.dumps(value, sort_keys=True).encode()).hexdigest()[:8]
