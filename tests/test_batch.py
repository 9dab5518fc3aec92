"""Batches (pds_plugin.batch, pds-mesh batch): many parts and planes, resumable, nothing lost.

Parts are built here with trimesh and manifold3d (so every test runs without shared
data), plus ../shared/data when present. Outputs are checked as files a user reads: the
PLY loads, its vertices lie in the job's plane, every triangle meets Theorem 1, its
SHA-256 is the one its record proves, and the same job meshed in this process gives the
same bytes. The Dask tests start a real LocalCluster with 2 worker processes.
"""

import json
import logging
import os
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
import trimesh

import pds_plugin as pds
from conftest import DATA
from pds_plugin.analysis.quality import ASPECT_BOUND
from pds_plugin.batch import RESULTS, mesh_batch, read_manifest
from pds_plugin.batch.jobs import parse_job
from pds_plugin.batch.worker import file_digest
from pds_plugin.cli import main
from pds_plugin.errors import ArgumentError
from pds_plugin.sources.demo import demo_part

STATUSES = {"ok", "error", "skipped", "cancelled"}


# --- parts and checks ----------------------------------------------------------------

@pytest.fixture(scope="module")
def parts(tmp_path_factory):
    """Small solids as mesh files: a ring (trimesh), the demo plate (manifold3d), a box,
    and a file that is not a mesh."""
    folder = tmp_path_factory.mktemp("parts")
    trimesh.creation.annulus(r_min=1, r_max=2, height=2).export(folder / "ring.stl")
    trimesh.creation.box(extents=(2, 2, 2)).export(folder / "box.stl")
    plate = demo_part().to_mesh64()
    trimesh.Trimesh(plate.vert_properties[:, :3], plate.tri_verts).export(folder / "plate.stl")
    (folder / "broken.stl").write_text("solid nothing\nthis is not an STL\n")
    return folder


def ring_jobs(count, alpha=0.2):
    """``count`` planes across the ring, each its own job."""
    return [{"input": "ring.stl", "axis": "z", "at": round(-0.9 + 1.8 * i / max(count - 1, 1), 6),
             "alpha": alpha} for i in range(count)]


def check_output(path, record):
    """A finished output: the bytes its record proves, a PLY whose triangles meet
    Theorem 1 (but the exceptions at small features its certificate lists, each within
    its proven aspect ratio: the sliced angle block has steps of 0.5 alpha), with one
    vertex per sample of its section report."""
    path = Path(path)
    assert not path.name.startswith(".")
    assert record["outputs"][str(path)] == file_digest(path)
    [section] = [s for s in record["sections"] if s["output"] == str(path)]
    mesh = trimesh.load_mesh(path, process=False)
    quality = mesh.metadata["_ply_raw"]["face"]["data"]["quality"]
    assert len(mesh.vertices) == section["samples"] and len(mesh.faces) == section["triangles"]
    bound = np.full(len(quality), ASPECT_BOUND)
    for exception in section["certificate"]["exceptions"]:
        bound[exception["triangle"]] = exception["proven_aspect_ratio"]
    assert (quality <= bound * (1 + 1e-9)).all()
    return mesh


def records_and_outputs(out_dir):
    """Every record in ``out_dir`` and the outputs it proves; the folder holds nothing
    else (no temporary or half-written file)."""
    records = {p: json.loads(p.read_text()) for p in Path(out_dir).rglob("*.ply.json")}
    proven = {Path(name) for record in records.values() for name in record["outputs"]}
    files = {p for p in Path(out_dir).rglob("*") if p.is_file()}
    assert files - proven - set(records) - {Path(out_dir) / RESULTS} == set()
    return records


def read_results(out_dir):
    return [json.loads(line) for line in (Path(out_dir) / RESULTS).read_text().splitlines()]


def mesh_here(job):
    """The job's mesh made in this process, as bytes (the determinism oracle)."""
    [region] = job.regions()
    settings = job.settings
    mesh = pds.mesh_region(region, settings["alpha"], seed=settings["seed"])
    out = Path(job.output).with_name("here.ply")
    mesh.export(out)
    data = out.read_bytes()
    out.unlink()
    return data


# --- jobs and manifests --------------------------------------------------------------

@pytest.mark.parametrize("job, message", [
    ({"axis": "z", "alpha": 0.1}, "no input"),
    ({"input": "p.stl", "axis": "z", "alpha": -1}, "alpha must be a positive number"),
    ({"input": "p.stl", "axis": "z", "alpha": "fine"}, "alpha must be a positive number"),
    ({"input": "p.stl", "axis": "w", "alpha": 0.1}, "axis must be one of x, y, z"),
    ({"input": "p.stl", "alpha": 0.1}, "is a solid: say where to cut it"),
    ({"input": "p.svg", "axis": "z", "alpha": 0.1}, "SVG drawing, which is already planar"),
    ({"input": "p.dxf", "slices": 2, "alpha": 0.1}, "DXF drawing, which is already planar"),
    ({"input": "p.svg", "layer": "A", "alpha": 0.1}, "layers of a DXF drawing"),
    ({"input": "p.stl", "plane_normal": "0,0,0", "alpha": 0.1}, "zero vector"),
    ({"input": "p.stl", "plane_normal": [1, 2], "alpha": 0.1}, "three numbers"),
    ({"input": "p.stl", "axis": "z", "at": "1,x", "alpha": 0.1}, "at must be finite numbers"),
    ({"input": "p.stl", "axis": "z", "slices": 0, "alpha": 0.1}, "positive integer"),
    ({"input": "p.stl", "axis": "z", "slices": 2, "at": 1, "alpha": 0.1}, "not both"),
    ({"input": "p.stl", "axis": "z", "alpha": 0.1, "graded": "maybe"}, "true or false"),
    ({"input": "p.stl", "axis": "z", "alpha": 0.1, "graded": "yes", "conforming": False},
     "graded meshes are always conforming"),
    ({"input": "p.stl", "axis": "z", "alpha": 0.1, "output": "p.xyz"}, "suffix must be"),
    ({"input": "p.stl", "axis": "z", "alpha": 0.1, "sead": 1}, "unknown option 'sead'"),
])
def test_bad_jobs_are_refused_with_the_option_named(job, message, tmp_path):
    with pytest.raises(ArgumentError, match=message):
        parse_job(job, 0, tmp_path)


def test_text_values_mean_the_same_as_typed_values(tmp_path):
    typed = parse_job({"input": "p.stl", "plane_normal": [0, 1, 1], "at": [0.5, 1],
                       "alpha": 0.25, "seed": 3, "graded": False, "conforming": False}, 0,
                      tmp_path)
    text = parse_job({"input": "p.stl", "plane_normal": "0,1,1", "at": "0.5,1",
                      "alpha": "0.25", "seed": "3", "graded": "false", "conforming": "no",
                      "slices": ""}, 0, tmp_path)
    assert typed == text and dict(typed.options)["conforming"] is False
    default = parse_job({"input": "p.stl", "axis": "z", "alpha": 0.25}, 0, tmp_path)
    assert dict(default.options)["conforming"] is True
    assert len(typed.outputs) == 2 and typed.outputs[0].endswith("_000.ply")


@pytest.mark.parametrize("options, command_line", [
    ({}, []),
    ({"graded": False}, ["--uniform"]),
    ({"alpha": 0.2}, ["--alpha", "0.2"]),
    ({"alpha": 0.2, "graded": True}, ["--alpha", "0.2", "--graded"]),
    ({"conforming": False}, ["--no-conforming"]),
])
def test_a_job_takes_alpha_and_grading_as_pds_mesh_does(options, command_line, tmp_path):
    """A manifest row without alpha is meshed at alpha auto, graded, as pds-mesh is; with
    any options the job is graded exactly when pds-mesh with the same options is."""
    from pds_plugin.cli.arguments import parser, wants_graded

    manifest = tmp_path / "jobs.csv"
    manifest.write_text(",".join(["input", "axis", *options]) + "\n"
                        + ",".join(["p.stl", "z", *map(str, options.values())]) + "\n")
    settings = parse_job(read_manifest(manifest)[0], 0, tmp_path).settings
    args = parser().parse_args(["mesh", "p.stl", "-o", "c.ply", "--axis", "z", *command_line])
    assert settings["alpha"] == args.alpha
    assert settings["graded"] is wants_graded(args)
    assert settings["graded"] is (not options or options == {"alpha": 0.2, "graded": True})


def test_manifests_in_json_lines_and_csv_give_the_same_jobs(tmp_path):
    (tmp_path / "jobs.jsonl").write_text(
        '# parts\n{"input": "ring.stl", "axis": "z", "at": 0.5, "alpha": 0.2}\n\n'
        '{"input": "logo.svg", "alpha": "auto"}\n')
    (tmp_path / "jobs.csv").write_text("input,axis,at,alpha\nring.stl,z,0.5,0.2\n"
                                       "logo.svg,,,auto\n")
    jsonl, csv = read_manifest(tmp_path / "jobs.jsonl"), read_manifest(tmp_path / "jobs.csv")
    assert [parse_job(j, i, tmp_path) for i, j in enumerate(jsonl)] == \
        [parse_job(j, i, tmp_path) for i, j in enumerate(csv)]


@pytest.mark.parametrize("name, text, message", [
    ("bad.jsonl", '{"input": "a.stl"}\n{"input": \n', "line 2: not JSON"),
    ("list.jsonl", '["a.stl"]\n', "line 1: a job is a JSON object"),
    ("empty.jsonl", "\n# nothing\n", "holds no job"),
    ("noheader.csv", "a.stl,z,0.1\n", "header row"),
])
def test_unreadable_manifests_say_where(name, text, message, tmp_path):
    (tmp_path / name).write_text(text)
    with pytest.raises(ArgumentError, match=message):
        read_manifest(tmp_path / name)


# --- mesh_batch on a thread pool (fast) ------------------------------------------------

def test_batch_meshes_every_job_and_reports_failures_without_stopping(parts, tmp_path):
    jobs = [*ring_jobs(2),
            {"input": "box.stl", "axis": "x", "slices": 2, "alpha": 0.3},
            {"input": "missing.stl", "axis": "z", "alpha": 0.2},
            {"input": "broken.stl", "axis": "z", "alpha": 0.2},
            {"input": "ring.stl", "axis": "z", "at": 5, "alpha": 0.2},        # misses
            {"input": "ring.stl", "axis": "z", "at": 0.1, "alpha": 0.2, "max_samples": 10},
            {"input": "ring.stl", "axis": "z", "at": 0.2, "alpha": 10,           # too large
             "conforming": False},            # (a conforming mesh keeps its boundary samples)
            {"input": "box.stl", "axis": "z", "alpha": 0.3, "output": "ring_z-0.9.ply"},
            {"input": "ring.stl", "axis": "z", "alpha": 0.2, "colour": "red"}]
    with ThreadPoolExecutor(2) as pool:
        rows = mesh_batch(jobs, tmp_path / "out", executor=pool, progress=False,
                          base_dir=parts)
    assert rows == read_results(tmp_path / "out")
    assert [row["job"] for row in rows] == list(range(len(jobs)))
    assert [row["status"] for row in rows] == ["ok"] * 3 + ["error"] * 7
    errors = [row["error"] for row in rows[3:]]
    assert "no such file" in errors[0] and "missing.stl" in errors[0]
    assert "broken.stl' has no triangles" in errors[1]
    assert "misses the solid" in errors[2]
    assert "more than max_samples=10" in errors[3]
    assert "no triangles" in errors[4] and "too large for the region" in errors[4]
    assert "also written by job 0" in errors[5]
    assert "unknown option 'colour'" in errors[6]
    records = records_and_outputs(tmp_path / "out")
    assert len(records) == 3
    ring = parse_job(jobs[0], 0, tmp_path / "out", parts)
    record = json.loads(ring.record.read_text())
    mesh = check_output(ring.output, record)
    assert np.allclose(mesh.vertices[:, 2], -0.9)                      # in the job's plane
    assert record["sections"][0]["certificate"]["betti_region"] == [1, 1]
    assert record["input_sha256"] == file_digest(parts / "ring.stl")
    assert record["certificate_ok"] is rows[0]["certificate_ok"] is True
    box = parse_job(jobs[2], 2, tmp_path / "out", parts)
    box_record = json.loads(box.record.read_text())
    for output, x in zip(rows[2]["output"], (-0.5, 0.5)):              # slabs' middles
        assert np.allclose(check_output(output, box_record).vertices[:, 0], x)


def test_a_graded_job_writes_a_graded_certified_mesh(parts, tmp_path):
    job = {"input": "ring.stl", "axis": "z", "alpha": "auto", "graded": "yes"}
    with ThreadPoolExecutor(1) as pool:
        [row] = mesh_batch([job], tmp_path, executor=pool, progress=False, base_dir=parts)
    assert row["status"] == "ok" and row["certificate_ok"] is True
    record = json.loads(parse_job(job, 0, tmp_path, parts).record.read_text())
    certificate = record["sections"][0]["certificate"]
    assert certificate["grading"] == 0.2 and certificate["betti_mesh"] == [1, 1]


def test_rerun_skips_done_jobs_untouched_and_redoes_what_changed(parts, tmp_path):
    source = tmp_path / "ring.stl"
    source.write_bytes((parts / "ring.stl").read_bytes())
    jobs = ring_jobs(3)
    out = tmp_path / "out"
    with ThreadPoolExecutor(2) as pool:
        first = mesh_batch(jobs, out, executor=pool, progress=False, base_dir=tmp_path)
        assert {row["status"] for row in first} == {"ok"}
        stamps = {p: (p.stat().st_mtime_ns, p.read_bytes()) for p in out.iterdir()
                  if p.name != RESULTS}
        again = mesh_batch(jobs, out, executor=pool, progress=False, base_dir=tmp_path)
        assert [row["status"] for row in again] == ["skipped"] * 3
        assert [row["output"] for row in again] == [row["output"] for row in first]
        assert {p: (p.stat().st_mtime_ns, p.read_bytes()) for p in stamps} == stamps

        jobs[1]["seed"] = 1                                 # other options: redone
        Path(first[2]["output"]).write_bytes(b"ply\ncorrupt")   # a damaged output: redone
        rows = mesh_batch(jobs, out, executor=pool, progress=False, base_dir=tmp_path)
        assert [row["status"] for row in rows] == ["skipped", "ok", "ok"]
        assert Path(first[2]["output"]).read_bytes() == stamps[Path(first[2]["output"])][1]

        trimesh.creation.annulus(r_min=0.5, r_max=2, height=2).export(source)  # new input
        rows = mesh_batch(jobs, out, executor=pool, progress=False, base_dir=tmp_path)
        assert [row["status"] for row in rows] == ["ok"] * 3
    records = records_and_outputs(out)
    assert all(r["input_sha256"] == file_digest(source) for r in records.values())


def test_leftovers_of_killed_writers_are_removed_for_this_batch_only(parts, tmp_path):
    [job] = ring_jobs(1)
    out = tmp_path / "out"
    out.mkdir()
    ours = out / ".ring_z-0.9.0123456789abcdef.tmp.ply"        # a SIGKILLed worker's
    # killed inside the PLY writer, whose own temporary name wraps the worker's
    nested = out / "..ring_z-0.9.0123456789abcdef.tmp.fedcba9876543210.tmp.ply"
    theirs = out / ".other.0123456789abcdef.tmp.ply"
    for path in (ours, nested, theirs):
        path.write_bytes(b"ply\nhalf")
    with ThreadPoolExecutor(1) as pool:
        mesh_batch([job], out, executor=pool, progress=False, base_dir=parts)
    assert not ours.exists() and not nested.exists() and theirs.exists()


def test_a_job_failing_after_success_leaves_no_stale_record(parts, tmp_path):
    source = tmp_path / "ring.stl"
    source.write_bytes((parts / "ring.stl").read_bytes())
    [job] = ring_jobs(1)
    with ThreadPoolExecutor(1) as pool:
        assert mesh_batch([job], tmp_path / "out", executor=pool, progress=False,
                          base_dir=tmp_path)[0]["status"] == "ok"
        source.write_text("not a mesh any more")
        [row] = mesh_batch([job], tmp_path / "out", executor=pool, progress=False,
                           base_dir=tmp_path)
    assert row["status"] == "error"
    assert not parse_job(job, 0, tmp_path / "out", tmp_path).record.exists()


def test_drawings_and_the_shared_parts(parts, tmp_path):
    if not DATA.is_dir():
        pytest.skip(f"{DATA} not available")
    jobs = [{"input": "MIL.svg", "alpha": 30.0},
            {"input": "featuretype.STL", "axis": "z", "alpha": 0.05},
            {"input": "angle_block.STL", "axis": "z", "slices": 2, "alpha": 0.04},
            {"input": "wrench.dxf", "alpha": 0.03}]
    with ThreadPoolExecutor(2) as pool:
        rows = mesh_batch(jobs, tmp_path, executor=pool, progress=False, base_dir=DATA)
    assert [row["status"] for row in rows] == ["ok"] * 4, rows
    records = records_and_outputs(tmp_path)
    betti = {Path(r["input"]).name: r["sections"][0]["certificate"]["betti_region"]
             for r in records.values()}
    assert betti["MIL.svg"] == [1, 8] and betti["featuretype.STL"] == [2, 8]   # data README
    for record in records.values():
        for output in record["outputs"]:
            check_output(output, record)


# --- the default executor: local spawned processes, and Ctrl-C ---------------------------

def run_cli(*args, **options):
    return subprocess.Popen([sys.executable, "-m", "pds_plugin.cli", "batch", *map(str, args)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            **options)


@pytest.mark.parametrize("presses", [1, 2])
def test_ctrl_c_leaves_no_partial_file_and_consistent_results(presses, parts, tmp_path):
    """Ctrl-C once: the running jobs finish, the queued ones are cancelled; twice: the
    workers are killed mid-job and their temporary files removed. Either way every mesh
    under a final name is complete and proven, and a rerun does exactly the rest."""
    manifest = tmp_path / "jobs.jsonl"
    jobs = [dict(job, input=str(parts / "ring.stl")) for job in ring_jobs(12, alpha=0.05)]
    manifest.write_text("".join(json.dumps(job) + "\n" for job in jobs))
    out = tmp_path / "out"
    batch = run_cli(manifest, "-o", out, "--workers", "2", start_new_session=True)
    deadline = time.monotonic() + 300
    while not list(out.glob("*.ply.json")) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert list(out.glob("*.ply.json")), "no job finished in 300 s"   # then interrupt
    for _ in range(presses):                # Ctrl-C: the whole process group
        os.killpg(batch.pid, signal.SIGINT)
        time.sleep(0.3)
    _, stderr = batch.communicate(timeout=120)
    assert batch.returncode == 130, stderr
    assert "Traceback" not in stderr, stderr
    rows = read_results(out)
    assert [row["job"] for row in rows] == list(range(len(jobs)))
    assert {row["status"] for row in rows} <= {"ok", "cancelled"}, rows
    assert "cancelled" in {row["status"] for row in rows}
    records = records_and_outputs(out)     # no temporary file, no output without record
    done = [row for row in rows if row["status"] == "ok"]
    # a worker killed between renaming the record and its mesh leaves a record that
    # proves nothing: the rerun redoes that job
    complete = [r for r in records.values() if all(map(os.path.exists, r["outputs"]))]
    assert len(complete) >= len(done) >= 1
    for row in done:
        check_output(row["output"], records[Path(row["output"] + ".json")])

    rerun = run_cli(manifest, "-o", out, "--workers", "1")
    _, stderr = rerun.communicate(timeout=300)
    assert rerun.returncode == 0, stderr
    statuses = [row["status"] for row in read_results(out)]
    assert statuses.count("skipped") == len(complete)
    assert statuses.count("ok") == len(jobs) - len(complete)


def test_local_workers_run_the_kernels_on_one_thread(tmp_path):
    """Even when the kernels were loaded before the pool's initializer ran (the main
    script imports pds_plugin.batch, as pds-mesh does)."""
    script = tmp_path / "threads.py"
    script.write_text("from pds_plugin import _parallel\n"
                      "from pds_plugin.batch import local_executor\n"
                      "if __name__ == '__main__':\n"
                      "    _parallel.set_threads(2)\n"
                      "    with local_executor(2) as pool:\n"
                      "        print(_parallel.get_threads(), "
                      "pool.submit(_parallel.get_threads).result())\n")
    result = subprocess.run([sys.executable, script], capture_output=True, text=True,
                            timeout=300)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["2", "1"]


def test_cli_usage_errors_exit_2(tmp_path, capsys):
    assert main(["batch", tmp_path / "none.jsonl", "-o", tmp_path]) == 2
    assert "no such manifest" in capsys.readouterr().err
    (tmp_path / "jobs.jsonl").write_text('{"input": "a.stl", "alpha": 1}\n')
    assert main(["batch", tmp_path / "jobs.jsonl"]) == 2
    assert main(["batch", tmp_path / "jobs.jsonl", "-o", tmp_path, "--workers", "0"]) == 2
    assert main(["batch", tmp_path / "jobs.jsonl", "-o", tmp_path, "--workers", "1",
                 "--scheduler", "tcp://nowhere:1"]) == 2
    capsys.readouterr()
    assert main(["batch", tmp_path / "jobs.jsonl", "-o", tmp_path,
                 "--scheduler", "tcp://127.0.0.1:1"]) == 2     # nobody listens there
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:1" in capsys.readouterr().err
    assert not (tmp_path / "results.jsonl").exists()


# --- Dask: a real LocalCluster with 2 worker processes ------------------------------------

@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0", env={"PDS_THREADS": "1"},
                                  silence_logs=logging.ERROR) as cluster, \
            distributed.Client(cluster) as client:
        yield cluster, client


def test_cli_on_a_dask_cluster_then_rerun_skips(cluster, parts, tmp_path):
    local, _ = cluster
    jobs = [*ring_jobs(3), {"input": "plate.stl", "axis": "z", "alpha": 0.1},
            {"input": "broken.stl", "axis": "z", "alpha": 0.1}]
    if DATA.is_dir():
        jobs += [{"input": str(DATA / "MIL.svg"), "alpha": 30.0},
                 {"input": str(DATA / "featuretype.STL"), "axis": "z", "alpha": 0.05}]
    manifest = parts / "cluster.jsonl"
    manifest.write_text("".join(json.dumps(job) + "\n" for job in jobs))
    out = tmp_path / "out"
    batch = run_cli(manifest, "-o", out, "--scheduler", local.scheduler_address)
    stdout, stderr = batch.communicate(timeout=300)
    assert batch.returncode == 1, stderr                # the broken file failed, alone
    rows = read_results(out)
    assert [row["status"] for row in rows] == ["ok"] * 4 + ["error"] + ["ok"] * (len(jobs) - 5)
    assert "broken.stl" in stderr and f"{len(jobs) - 1} ok" in stdout
    records = records_and_outputs(out)
    assert len(records) == len(jobs) - 1
    for record in records.values():
        for output in record["outputs"]:
            check_output(output, record)
    ring = parse_job(jobs[0], 0, out, parts)
    assert Path(ring.output).read_bytes() == mesh_here(ring)    # same bytes as in here

    rerun = run_cli(manifest, "-o", out, "--scheduler", local.scheduler_address)
    _, stderr = rerun.communicate(timeout=300)
    assert rerun.returncode == 1, stderr
    assert [row["status"] for row in read_results(out)] == \
        ["skipped"] * 4 + ["error"] + ["skipped"] * (len(jobs) - 5)


def test_a_killed_worker_loses_nothing(cluster, parts, tmp_path):
    _, client = cluster
    jobs = [dict(job, input=str(parts / "ring.stl")) for job in ring_jobs(12, alpha=0.04)]
    out = tmp_path / "out"
    done = {}
    batch = threading.Thread(target=lambda: done.update(rows=mesh_batch(
        jobs, out, executor=client.get_executor(), progress=False)))
    batch.start()
    deadline = time.monotonic() + 120
    while not list(out.glob("*.ply.json")) and time.monotonic() < deadline:
        time.sleep(0.05)
    _, pid = sorted(client.run(os.getpid).items())[0]
    os.kill(pid, signal.SIGKILL)                        # mid-batch, mid-task
    assert len(list(out.glob("*.ply.json"))) < len(jobs)
    batch.join(timeout=600)
    assert not batch.is_alive()
    assert pid not in client.run(os.getpid).values()    # it died (its nanny restarts it)
    rows = done["rows"]
    # a task whose worker died after writing its record is redone as "skipped"
    assert {row["status"] for row in rows} <= {"ok", "skipped"}, rows
    records = records_and_outputs(out)                  # nothing half-written left
    assert sorted(records) == sorted(Path(row["output"] + ".json") for row in rows)
    assert len({row["output"] for row in rows}) == len(jobs)
    for row in rows:
        check_output(row["output"], records[Path(row["output"] + ".json")])


def test_a_rerun_in_the_same_client_redoes_deleted_outputs(cluster, parts, tmp_path):
    """Dask caches pure tasks by their arguments: a rerun must not get the old rows."""
    _, client = cluster
    jobs = ring_jobs(2)
    first = mesh_batch(jobs, tmp_path, executor=client.get_executor(), progress=False,
                       base_dir=parts)
    Path(first[0]["output"]).unlink()
    again = mesh_batch(jobs, tmp_path, executor=client.get_executor(), progress=False,
                       base_dir=parts)
    assert [row["status"] for row in again] == ["ok", "skipped"]
    check_output(first[0]["output"], json.loads(Path(first[0]["output"] + ".json").read_text()))
