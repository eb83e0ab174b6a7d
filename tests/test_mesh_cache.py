"""Mesh cache (meshing/cache.py): the key follows the parameters and the source of every
module that shapes a mesh, a moved module stops the build instead of dropping out of the key,
and a corrupt or truncated entry is named on stderr and rebuilt. Pure python, no gmsh: the
builders write a few bytes, and the cache lives in a tmp_path (PLANETARY_CACHE)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from meshing import cache

ROOT = Path(__file__).resolve().parent.parent
PROBE = "mesh_cache_probe"  # a module written into tmp_path, never imported


@pytest.fixture
def fresh_version():
    """Recompute the source version in this test and again after it (other tests must not
    see a version made of a temporary module list)."""
    cache.source_version.cache_clear()
    yield
    cache.source_version.cache_clear()


@pytest.fixture
def probe(tmp_path, monkeypatch, fresh_version) -> Path:
    """The module list reduced to one temporary module; the cache in tmp_path."""
    src = tmp_path / "src"
    src.mkdir()
    path = src / f"{PROBE}.py"
    path.write_text("X = 1\n")
    monkeypatch.syspath_prepend(str(src))
    monkeypatch.setattr(cache, "MESH_MODULES", (PROBE,))
    monkeypatch.setattr(cache, "AUTO_PACKAGES", ())
    monkeypatch.setenv("PLANETARY_CACHE", str(tmp_path / "cache"))
    return path


class Builder:
    """Writes ``payload`` into the given path and counts its calls."""

    def __init__(self, payload: bytes = b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n" * 40):
        self.payload = payload
        self.calls = 0

    def __call__(self, path: Path) -> dict:
        self.calls += 1
        path.write_bytes(self.payload)
        return {"elements": 123, "min_sicn": 0.5}


# ---------------------------------------------------------------------------------------
# key and source version
# ---------------------------------------------------------------------------------------


def test_key_follows_parameters(probe):
    k26 = cache.key("body", {"teeth": 26, "module": 2.0})
    assert cache.key("body", {"module": 2.0, "teeth": 26}) == k26  # canonical, order-free
    assert cache.key("body", {"teeth": 27, "module": 2.0}) != k26
    assert cache.key("carrier", {"teeth": 26, "module": 2.0}) != k26


def test_key_follows_module_source(probe):
    v1 = cache.source_version()
    k1 = cache.key("body", {"teeth": 26})
    probe.write_text("X = 2\n")
    assert cache.source_version() == v1  # computed once per process
    cache.source_version.cache_clear()
    assert cache.source_version() != v1
    assert cache.key("body", {"teeth": 26}) != k1
    probe.write_text("X = 1\n")
    cache.source_version.cache_clear()
    assert cache.source_version() == v1  # the text, not the file's time, makes the version


@pytest.mark.parametrize("missing", ["meshing.no_such_module", "no_such_package.geometry"])
def test_missing_module_is_a_clear_error(probe, monkeypatch, missing):
    monkeypatch.setattr(cache, "MESH_MODULES", (PROBE, missing))
    with pytest.raises(RuntimeError, match=r"MESH_MODULES in meshing/cache\.py") as info:
        cache.source_version()
    assert repr(missing) in str(info.value)
    with pytest.raises(RuntimeError, match="not found"):
        cache.key("body", {"teeth": 26})


def test_every_listed_module_is_found_in_this_tree(fresh_version):
    sources = cache.hashed_sources()
    for name in cache.MESH_MODULES:
        assert name in sources, name
        assert sources[name].resolve().is_relative_to(ROOT), (
            f"{name} resolves to {sources[name]}, outside {ROOT} (a stale installed copy?)"
        )


def test_gears_package_files_are_hashed(fresh_version):
    hashed = {p.resolve() for p in cache.hashed_sources().values()}
    gears = {p.resolve() for p in (ROOT / "gears").glob("*.py")}
    assert {"involute.py", "spec.py", "profile.py", "pair.py"} <= {p.name for p in gears}
    assert sorted(gears - hashed) == []


def test_every_meshing_module_is_classified():
    """A new meshing module (e.g. a split of gear_body.py or scenes.py) must be put either in
    MESH_MODULES or in NOT_MESH_SHAPING: forgetting it would leave it out of the key."""
    found = {f"meshing.{p.stem}" for p in (ROOT / "meshing").glob("*.py")} - {"meshing.__init__"}
    listed, skipped = set(cache.MESH_MODULES), set(cache.NOT_MESH_SHAPING)
    assert not listed & skipped
    assert sorted(found - listed - skipped) == []
    assert sorted(skipped - found) == []  # no stale exclusions


# ---------------------------------------------------------------------------------------
# get_or_build: reuse, corruption, cache folder
# ---------------------------------------------------------------------------------------


def test_builds_once_then_reuses(probe, capsys):
    build = Builder()
    params = {"teeth": 26}
    msh, meta = cache.get_or_build("body", params, build)
    assert build.calls == 1 and meta["cached"] is False
    assert msh.read_bytes() == build.payload
    side = json.loads(msh.with_suffix(".json").read_text())
    assert side["msh_bytes"] == len(build.payload) and side["elements"] == 123
    assert "cached" not in side
    # nothing left over from the atomic writes
    assert sorted(p.name for p in msh.parent.iterdir()) == sorted([msh.name, msh.stem + ".json"])

    msh2, meta2 = cache.get_or_build("body", params, build)
    assert build.calls == 1 and meta2["cached"] is True
    assert msh2 == msh and meta2["elements"] == 123 and meta2["params"] == {"teeth": 26}

    cache.get_or_build("body", {"teeth": 27}, build)
    assert build.calls == 2
    _, meta3 = cache.get_or_build("body", params, build, rebuild=True)
    assert build.calls == 3 and meta3["cached"] is False
    assert capsys.readouterr().err == ""


def _bad_json(msh: Path, side: Path) -> Path:
    side.write_text('{"elements": 123, "msh_bytes"')
    return side


def _lacks_keys(msh: Path, side: Path) -> Path:
    side.write_text(json.dumps({"elements": 123}))
    return side


def _truncated(msh: Path, side: Path) -> Path:
    msh.write_bytes(msh.read_bytes()[:-7])
    return msh


def _empty(msh: Path, side: Path) -> Path:
    msh.write_bytes(b"")
    return msh


def _same_size_other_bytes(msh: Path, side: Path) -> Path:
    data = bytearray(msh.read_bytes())
    data[len(data) // 2] ^= 0xFF
    msh.write_bytes(bytes(data))
    return msh


def _no_sidecar(msh: Path, side: Path) -> Path:
    side.unlink()
    return msh


@pytest.mark.parametrize(
    ("damage", "why"),
    [
        (_bad_json, "does not parse"),
        (_lacks_keys, "lacks"),
        (_truncated, "bytes, the sidecar records"),
        (_empty, "empty"),
        (_same_size_other_bytes, "sha256"),
        (_no_sidecar, "no sidecar"),
    ],
)
def test_corrupt_entry_is_named_and_rebuilt(probe, capsys, damage, why):
    build = Builder()
    msh, _ = cache.get_or_build("body", {"teeth": 26}, build)
    bad = damage(msh, msh.with_suffix(".json"))
    capsys.readouterr()

    msh2, meta = cache.get_or_build("body", {"teeth": 26}, build)
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert f"mesh cache entry {bad} is corrupt (" in err and why in err
    assert err.rstrip().endswith(": rebuilding")
    assert build.calls == 2 and meta["cached"] is False
    assert msh2.read_bytes() == build.payload

    _, meta = cache.get_or_build("body", {"teeth": 26}, build)  # sound again
    assert build.calls == 2 and meta["cached"] is True
    assert capsys.readouterr().err == ""


def test_failed_build_leaves_no_entry(probe):
    def fails(path: Path) -> dict:
        path.write_bytes(b"half a mesh")
        raise ValueError("gmsh gave up")

    with pytest.raises(ValueError, match="gmsh gave up"):
        cache.get_or_build("body", {"teeth": 26}, fails)
    with pytest.raises(RuntimeError, match="wrote nothing"):
        cache.get_or_build("body", {"teeth": 26}, lambda path: {"elements": 0})
    assert list(cache.cache_dir().iterdir()) == []


@pytest.mark.parametrize("below", [None, "sub"])
def test_cache_folder_that_is_a_file_is_a_clear_error(tmp_path, monkeypatch, probe, below):
    f = tmp_path / "not-a-folder"
    f.write_text("x")
    target = f if below is None else f / below
    monkeypatch.setenv("PLANETARY_CACHE", str(target))
    build = Builder()
    with pytest.raises(cache.CacheDirError) as info:
        cache.get_or_build("body", {"teeth": 26}, build)
    msg = str(info.value)
    assert str(target) in msg and "set PLANETARY_CACHE to a writable folder" in msg
    assert build.calls == 0


class FakeComm:
    """``bcast`` of a two-rank communicator seen from one rank: rank 0 returns what it sends,
    rank 1 returns what rank 0 is taken to have sent (``from_root``, in order)."""

    def __init__(self, rank: int, from_root=()):
        self.rank = rank
        self.from_root = list(from_root)
        self.sent = []

    def bcast(self, obj, root=0):
        self.sent.append(obj)
        return obj if self.rank == 0 else self.from_root.pop(0)


def test_mpi_rank0_builds_and_errors_reach_every_rank(probe):
    build = Builder()
    comm0 = FakeComm(0)
    _, meta = cache.get_or_build("body", {"teeth": 26}, build, comm=comm0)
    assert build.calls == 1 and comm0.sent == [None, meta]

    comm1 = FakeComm(1, [None, {"elements": 123, "cached": True}])
    _, meta = cache.get_or_build("body", {"teeth": 27}, build, comm=comm1)
    assert build.calls == 1 and meta == {"elements": 123, "cached": True}  # rank 1 never builds

    comm1 = FakeComm(1, ["ValueError: gmsh gave up"])
    with pytest.raises(RuntimeError, match="failed on rank 0: ValueError: gmsh gave up"):
        cache.get_or_build("body", {"teeth": 27}, build, comm=comm1)
    assert comm1.from_root == []  # no second collective after a rank-0 error
