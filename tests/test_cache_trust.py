"""The compiled-code disk cache trusts only itself (issue 20, item 1).

Every set-up plants a cache entry whose unpickling would create a marker file (as planted
code would run) and checks that the marker never appears and that the build still succeeds
without the cache. The plants are well-formed entries, tagged with the cache's own key
where the set-up allows it, so each is refused by the check under test alone: the first
test shows the same plant *is* run from a trusted cache.
"""

import hashlib
import json
import os
import pickle
import shutil
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from mechcont.equations import _cache, _codegen

ROOT = Path(__file__).resolve().parents[1]
NOBODY = 65534
needs_root = pytest.mark.skipif(os.geteuid() != 0, reason="making files owned by another user needs root")
pytestmark = pytest.mark.skipif(_codegen.backend() != "llvm", reason="the cache is used only with the LLVM backend")


class _Plant:
    """Unpickling this creates the file ``marker``: planted code that ran."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return (open, (self.marker, "w"))


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A fresh private cache made by the module (root, key file); its root path."""
    root = tmp_path / "cache"
    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(root))
    monkeypatch.delenv("MECHCONT_NO_CACHE", raising=False)
    monkeypatch.setattr(_cache, "_DISTRUSTED", {})
    assert _cache.store(_cache.cache_key(["trust test: another entry"]), "other")
    return root


@pytest.fixture
def parts(tmp_path):
    """A key of this test only, in a shard folder of its own: not the one of the cache fixture's other
    entry (the first two hex digits of the key; they coincided once in 256 runs)."""
    taken = _cache.cache_key(["trust test: another entry"])[:2]
    n = 0
    while _cache.cache_key(["trust test", str(tmp_path), str(n)])[:2] == taken:
        n += 1
    return ["trust test", str(tmp_path), str(n)]


def _entry(root: Path, parts) -> Path:
    key = _cache.cache_key(parts)
    return root / key[:2] / f"{key}.pkl"


def _plant(path: Path, parts, marker: Path, secret: bytes) -> bytes:
    """Write at ``path`` a well-formed entry for ``parts`` holding the plant, tagged with ``secret``."""
    data = _cache._encode(_cache.cache_key(parts), pickle.dumps(_Plant(marker)), secret)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data)
    return data


def _secret(root: Path) -> bytes:
    return (root / "hmac-key").read_bytes()


def _builds_without_the_cache(parts, marker: Path) -> None:
    built = []
    assert _cache.cached(parts, lambda: built.append(1) or "built") == "built"
    assert built == [1] and not marker.exists()


def _refused_once(capsys, where: Path, why: str) -> str:
    """The one warning on stderr, which names ``where`` and says ``why``."""
    err = capsys.readouterr().err
    assert err.count("mechcont: not using the compiled-code cache") == 1, err
    assert str(where) in err and why in err and "MECHCONT_CACHE_DIR" in err and len(err.splitlines()) == 1
    return err


def test_the_plant_runs_from_a_trusted_cache(cache, parts, tmp_path):
    """Control: a correctly tagged plant in a private cache is unpickled, so the refusals below are real."""
    marker = tmp_path / "marker"
    _plant(_entry(cache, parts), parts, marker, _secret(cache))
    _cache.load(_cache.cache_key(parts))
    assert marker.exists()


def test_root_is_a_symlink(cache, parts, tmp_path, monkeypatch, capsys):
    marker = tmp_path / "marker"
    data = _plant(_entry(cache, parts), parts, marker, _secret(cache))
    link = tmp_path / "link"
    link.symlink_to(cache)
    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(link))
    _builds_without_the_cache(parts, marker)
    _refused_once(capsys, link, "is a symbolic link")
    _builds_without_the_cache(parts, marker)  # once refused, no second warning, nothing written
    assert capsys.readouterr().err == "" and _entry(cache, parts).read_bytes() == data


def test_shard_folder_is_a_symlink(cache, parts, tmp_path, capsys):
    marker = tmp_path / "marker"
    entry = _entry(cache, parts)
    elsewhere = tmp_path / "elsewhere"
    _plant(elsewhere / entry.name, parts, marker, _secret(cache))
    elsewhere.chmod(0o700)
    entry.parent.symlink_to(elsewhere)
    _builds_without_the_cache(parts, marker)
    _refused_once(capsys, entry.parent, "is a symbolic link")


def test_entry_is_a_symlink(cache, parts, tmp_path, capsys):
    marker = tmp_path / "marker"
    target = tmp_path / "target.pkl"
    _plant(target, parts, marker, _secret(cache))
    entry = _entry(cache, parts)
    entry.parent.mkdir(mode=0o700)
    entry.symlink_to(target)
    _builds_without_the_cache(parts, marker)
    assert not entry.is_symlink() and _cache.load(_cache.cache_key(parts)) == "built"  # replaced by a good entry
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("where", ["root", "shard"])
def test_folder_writable_by_others(cache, parts, tmp_path, capsys, where):
    marker = tmp_path / "marker"
    entry = _entry(cache, parts)
    _plant(entry, parts, marker, _secret(cache))
    folder = cache if where == "root" else entry.parent
    folder.chmod(0o777)
    _builds_without_the_cache(parts, marker)
    _refused_once(capsys, folder, f"chmod 700 {folder}")
    assert folder.stat().st_mode & 0o777 == 0o777  # told, not changed behind the user's back


@needs_root
def test_root_owned_by_another_user(cache, parts, tmp_path, capsys):
    """A 0777 cache of `nobody`'s, entries tagged with its own key by `nobody`, used by root."""
    marker = tmp_path / "marker"
    entry = _entry(cache, parts)
    _plant(entry, parts, marker, _secret(cache))
    for p in (cache, *cache.rglob("*")):
        os.chown(p, NOBODY, NOBODY)
    cache.chmod(0o777)
    _builds_without_the_cache(parts, marker)
    _refused_once(capsys, cache, f"owned by user id {NOBODY}")


@needs_root
def test_entry_owned_by_another_user(cache, parts, tmp_path, capsys):
    marker = tmp_path / "marker"
    entry = _entry(cache, parts)
    _plant(entry, parts, marker, _secret(cache))
    os.chown(entry, NOBODY, NOBODY)
    _builds_without_the_cache(parts, marker)
    assert entry.stat().st_uid == os.geteuid()  # rewritten by this user
    assert capsys.readouterr().err == ""


def test_entry_writable_by_others(cache, parts, tmp_path):
    marker = tmp_path / "marker"
    entry = _entry(cache, parts)
    _plant(entry, parts, marker, _secret(cache))
    entry.chmod(0o622)
    _builds_without_the_cache(parts, marker)


def test_entry_without_a_valid_tag(cache, parts, tmp_path):
    """The right key in the header, but a forged, missing or foreign tag, or the old format."""
    marker = tmp_path / "marker"
    entry = _entry(cache, parts)
    key = _cache.cache_key(parts)
    payload = pickle.dumps(_Plant(marker))
    header = _cache._header(key)
    foreign = _cache._encode(key, payload, os.urandom(32))  # tagged with another cache's key
    old = b"mechcont-compiled-cache 1\n"
    old += hashlib.sha256(pickle.dumps((key, _Plant(marker)))).digest() + pickle.dumps((key, _Plant(marker)))
    for bad in (header + bytes(32) + payload, header + payload, foreign, old):
        _plant(entry, parts, marker, _secret(cache))
        entry.write_bytes(bad)
        _builds_without_the_cache(parts, marker)
        assert entry.read_bytes() != bad  # rewritten
    assert _cache.load(key) == "built"


def test_truncated_or_altered_entry(cache, parts, tmp_path):
    marker = tmp_path / "marker"
    entry = _entry(cache, parts)
    good = _plant(entry, parts, marker, _secret(cache))
    n = len(_cache._header(_cache.cache_key(parts)))
    for bad in (good[:n - 1], good[:n + 16], good[:n + 32], good[:-1], good[:-1] + bytes([good[-1] ^ 1]), good + b"\0"):
        entry.write_bytes(bad)
        _builds_without_the_cache(parts, marker)


def test_oversize_entry(cache, parts, tmp_path, monkeypatch):
    marker = tmp_path / "marker"
    entry = _entry(cache, parts)
    good = _plant(entry, parts, marker, _secret(cache))
    monkeypatch.setattr(_cache, "_MAX_ENTRY", len(good) - 1)
    _builds_without_the_cache(parts, marker)
    assert entry.read_bytes() != good  # the small rebuilt entry replaced it
    assert _cache.store(_cache.cache_key(parts), "x" * len(good)) is False  # one over the bound is not written
    monkeypatch.undo()
    with open(entry, "r+b") as f:  # sparse: past the real bound without using the disk
        f.truncate(_cache._MAX_ENTRY + 1)
    _builds_without_the_cache(parts, marker)


_IN_A_PROCESS = """
import json, sys
from mechcont.equations import _cache
print(json.dumps({"out": _cache.cached(json.loads(sys.argv[1]), lambda: "built"), "stats": _cache.STATS}))
"""


def _run(parts, env=None, timeout=120, **kw):
    """``cached(parts, build)`` in a new process (killed after ``timeout`` s): its result and stderr."""
    full = {**os.environ, "PYTHONPATH": str(ROOT / "src"), **(env or {})}
    r = subprocess.run([sys.executable, "-c", _IN_A_PROCESS, json.dumps(parts)], capture_output=True, text=True,
                       env=full, timeout=timeout, cwd=ROOT, **kw)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1]), r.stderr


def test_fifo_entry_does_not_hang(cache, parts):
    entry = _entry(cache, parts)
    entry.parent.mkdir(mode=0o700)
    os.mkfifo(entry, 0o600)
    out, err = _run(parts, timeout=60)
    assert out["out"] == "built" and out["stats"]["writes"] == 1 and err == ""
    assert entry.is_file()  # replaced by a good entry
    fifo = entry.with_name("fifo")
    os.mkfifo(fifo, 0o600)
    assert _not_regular(fifo)


def _not_regular(path: Path) -> bool:
    """The reader refuses ``path`` as not a regular file (its size-bounded read alone would read nothing)."""
    fd = os.open(path.parent, os.O_RDONLY)
    try:
        return _cache._read_file(path.name, fd, 0o022, 1 << 20) == (None, "is not a regular file")
    finally:
        os.close(fd)


def test_link_to_dev_zero(cache, parts):
    entry = _entry(cache, parts)
    entry.parent.mkdir(mode=0o700)
    entry.symlink_to("/dev/zero")
    out, err = _run(parts, timeout=60)
    assert out["out"] == "built" and err == ""


@needs_root
def test_device_node_entry(cache, parts):
    """Not a link but a device itself (only root can make one): refused as not a regular file."""
    entry = _entry(cache, parts)
    entry.parent.mkdir(mode=0o700)
    os.mknod(entry, 0o600 | stat.S_IFCHR, os.makedev(1, 5))  # /dev/zero's numbers
    out, _ = _run(parts, timeout=60)
    assert out["out"] == "built"
    os.mknod(entry.with_name("zero"), 0o600 | stat.S_IFCHR, os.makedev(1, 5))
    assert _not_regular(entry.with_name("zero"))


@pytest.mark.parametrize("bad", ["symlink", "group-readable"])
def test_bad_key_file(cache, parts, tmp_path, capsys, bad):
    marker = tmp_path / "marker"
    key_file = cache / "hmac-key"
    if bad == "symlink":  # to a key the planter knows
        known = tmp_path / "known-key"
        known.write_bytes(b"k" * 32)
        known.chmod(0o600)
        key_file.unlink()
        key_file.symlink_to(known)
        _plant(_entry(cache, parts), parts, marker, b"k" * 32)
        why = "is a symbolic link"
    else:
        _plant(_entry(cache, parts), parts, marker, _secret(cache))
        key_file.chmod(0o640)
        why = "readable or writable by group or others"
    _builds_without_the_cache(parts, marker)
    assert f"delete {key_file}" in _refused_once(capsys, key_file, why)


def test_made_private_whatever_the_umask(tmp_path, monkeypatch, parts):
    root = tmp_path / "new" / "cache"
    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(root))
    monkeypatch.delenv("MECHCONT_NO_CACHE", raising=False)
    old = os.umask(0)
    try:
        assert _cache.store(_cache.cache_key(parts), "x")
    finally:
        os.umask(old)
    entry = _entry(root, parts)
    assert [p.stat().st_mode & 0o777 for p in (root, entry.parent, root / "hmac-key", entry)] == [0o700, 0o700, 0o600, 0o600]
    assert _cache.load(_cache.cache_key(parts)) == "x"
    assert not list(root.rglob(".tmp-*"))


def test_keys_are_only_hexadecimal_digests(cache):
    assert _cache.store("../../escape", "x") is False and _cache.load("../../escape") is None
    assert not (cache.parent / "escape.pkl").exists()


_AS_NOBODY = f"""
import json, os, secrets, sys  # secrets: _cache imports it when writing; this Python lives where nobody cannot read
from mechcont.equations import _cache
parts, theirs, mine, marker = json.loads(sys.argv[1])
key = _cache.cache_key(parts)  # the key needs the sources: read them before dropping to nobody
class Plant:
    def __reduce__(self):
        return (open, (marker, "w"))
os.setgroups([]); os.setgid({NOBODY}); os.setuid({NOBODY})
os.environ["MECHCONT_CACHE_DIR"] = theirs
out = _cache.cached(parts, lambda: "built")
os.environ["MECHCONT_CACHE_DIR"] = mine
stored = _cache.store(key, Plant())
print(json.dumps({{"out": out, "stored": stored, "euid": os.geteuid()}}))
"""


@needs_root
def test_another_users_process(parts, monkeypatch, capsys):
    """`nobody` refuses root's readable cache; root refuses the cache `nobody` filled with a plant."""
    shared = Path(tempfile.mkdtemp(prefix="mechcont-trust-"))  # outside pytest's root-only folders
    try:
        shared.chmod(0o755)
        drop = shared / "drop"
        drop.mkdir()
        drop.chmod(0o777)  # where nobody's plant could write, so a refusal is not mere lack of access
        marker = drop / "marker"
        roots = shared / "root-cache"
        monkeypatch.setenv("MECHCONT_CACHE_DIR", str(roots))
        monkeypatch.delenv("MECHCONT_NO_CACHE", raising=False)
        monkeypatch.setattr(_cache, "_DISTRUSTED", {})
        assert _cache.store(_cache.cache_key(["root's"]), "root's")
        entry = _entry(roots, parts)
        _plant(entry, parts, marker, _secret(roots))
        for p in (roots, entry.parent):
            p.chmod(0o755)
        entry.chmod(0o644)
        nobodys = drop / "nobody-cache"
        r = subprocess.run([sys.executable, "-c", _AS_NOBODY, json.dumps([parts, str(roots), str(nobodys), str(marker)])],
                           capture_output=True, text=True, timeout=120, cwd=ROOT,
                           env={**os.environ, "PYTHONPATH": str(ROOT / "src"), "HOME": str(drop)})
        assert r.returncode == 0, r.stderr
        out = json.loads(r.stdout.strip().splitlines()[-1])
        assert out == {"out": "built", "stored": True, "euid": NOBODY}
        assert f"{roots} is owned by user id 0" in r.stderr and not marker.exists()
        assert _entry(nobodys, parts).stat().st_uid == NOBODY
        # root, pointed at nobody's cache (a valid entry, tagged with nobody's key), refuses it
        monkeypatch.setenv("MECHCONT_CACHE_DIR", str(nobodys))
        _builds_without_the_cache(parts, marker)
        _refused_once(capsys, nobodys, f"owned by user id {NOBODY}")
    finally:
        shutil.rmtree(shared, ignore_errors=True)


_MODEL = """
import json
import numpy as np
from mechcont.equations import _cache, _codegen
from mechcont.models import load_model
m = load_model("overcentre", LU=0.4)
r, J = m.residual_and_jacobian(m.defaults())
print(json.dumps({"r": r.tolist(), "J": np.asarray(J).tolist(), "compiled": _codegen.COUNTS["compiled"],
                  "stats": _cache.STATS}))
"""


def test_a_real_model_round_trips_through_the_trusted_cache(tmp_path):
    import numpy as np

    env = {**os.environ, "PYTHONPATH": str(ROOT / "src"), "MECHCONT_CACHE_DIR": str(tmp_path / "c"), "MECHCONT_NO_CACHE": ""}
    outs = []
    for _ in range(2):
        r = subprocess.run([sys.executable, "-c", _MODEL], capture_output=True, text=True, env=env, timeout=300, cwd=ROOT)
        assert r.returncode == 0 and r.stderr == "", r.stderr
        outs.append(json.loads(r.stdout.strip().splitlines()[-1]))
    first, second = outs
    assert first["compiled"] > 0 and first["stats"]["writes"] > 0
    assert second["compiled"] == 0 and second["stats"]["misses"] == 0 and second["stats"]["hits"] > 0
    assert np.allclose(second["r"], first["r"], rtol=1e-12, atol=1e-12)
    assert np.allclose(second["J"], first["J"], rtol=1e-12, atol=1e-12)
    assert all(p.stat().st_uid == os.geteuid() and p.stat().st_mode & 0o077 == 0 for p in (tmp_path / "c").rglob("*"))


_BUILD_ONCE = r"""
import json, sys, time
from mechcont.equations import _cache
def build():
    with open(sys.argv[1], "a") as f:
        f.write("built\n")
    time.sleep(3.0)  # long enough that the other process asks for the entry while this one builds it
    return {"value": 42}
print(json.dumps(_cache.load_or_build(_cache.cache_key(["built once"]), build)))
"""


def test_two_processes_that_need_one_entry_build_it_once(tmp_path):
    """The second waits for the first's build (a lock beside the entry) and loads it: both get the object."""
    if _codegen.backend() != "llvm":
        pytest.skip("entries are stored only with SymEngine's LLVM backend")
    env = {**os.environ, "MECHCONT_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT / "src")}
    env.pop("MECHCONT_NO_CACHE", None)
    log = tmp_path / "builds"
    procs = [subprocess.Popen([sys.executable, "-c", _BUILD_ONCE, str(log)], env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(2)]
    results = [p.communicate(timeout=300) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], [err for _, err in results]
    assert [json.loads(out.strip().splitlines()[-1]) for out, _ in results] == [{"value": 42}] * 2
    assert log.read_text() == "built\n"
