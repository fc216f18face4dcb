"""Hostile ``--scheduler`` addresses, for every command that takes one (sweep and risk): each
is refused with one paragraph (exit 2) that says what is wrong and how to give the address,
within bounded time (a refused port at once; a service that accepts and never answers, or
answers in another protocol, within the handshake's time), and leaves nothing behind (no
``OUT.parts`` folder, no lock, no output). Fake services run on loopback in threads."""

from __future__ import annotations

import socket
import threading
from pathlib import Path

import pytest

pytest.importorskip("distributed")

from pframe.cli import main  # noqa: E402
from pframe.errors import InputError  # noqa: E402
from pframe.sweep import cluster  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
SCENE = """\
buildings:
  - {name: A, floors: 1, mass: 1000.0, story: {material: elastic, stiffness: 1.0e6}}
  - {name: B, floors: 1, mass: 1000.0, story: {material: elastic, stiffness: 2.0e6}}
contacts:
  - {nodes: [A/1, B/1], gap: 0.01, law: linear, stiffness: 1.0e7}
excitation: {kind: sine, amplitude: 3.0, frequency: 6.0}
analysis: {dt: 0.002, duration: 0.1}
"""
SWEEP = """\
base: scene.yaml
axes:
  - {name: gap, path: contacts.*.gap, values: [0.01, 0.02]}
chunk: 1
"""

#: malformed addresses, generated: no port, a port out of range or not a number, a scheme
#: Dask's TCP client does not speak, an unclosed IPv6 bracket, nothing at all
MALFORMED = ([f"{scheme}{host}" for scheme in ("", "tcp://", "TCP://", "tls://")
              for host in ("localhost", "127.0.0.1", "[::1]", "node-7.cluster")]
             + [f"tcp://127.0.0.1:{port}" for port in ("0", "65536", "99999", "-1", "80a",
                                                       "", " ")]
             + [f"{scheme}://127.0.0.1:8786" for scheme in ("http", "https", "ucx", "inproc",
                                                           "bogus")]
             + ["tcp://[::1", "tcp://[nothex]:8786", "tcp://a:b:c", "", "   ", "://:8786"])


@pytest.mark.parametrize("address", MALFORMED)
def test_a_malformed_address_is_refused_by_its_form(address):
    with pytest.raises(InputError) as info:
        cluster.parse(address)
    message = str(info.value)
    assert "tcp://HOST:PORT" in message and "\n" not in message


@pytest.mark.parametrize("address, expected", [
    ("127.0.0.1:8786", ("tcp", "127.0.0.1", 8786)),
    ("tcp://localhost:1", ("tcp", "localhost", 1)),
    ("tls://node-7.cluster:65535", ("tls", "node-7.cluster", 65535)),
    ("tcp://[::1]:8786", ("tcp", "::1", 8786)),
])
def test_a_well_formed_address_is_read(address, expected):
    assert cluster.parse(address) == expected


class _Service:
    """A loopback TCP service: ``mode`` silent (accepts, never answers), banner (sends an SSH
    greeting at once), http (answers only a request: waits for a line that Dask never
    sends)."""

    def __init__(self, mode: str):
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(16)
        self.port = self.sock.getsockname()[1]
        self.mode = mode
        self.accepted = []
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            self.accepted.append(conn)
            if self.mode == "banner":
                conn.sendall(b"SSH-2.0-OpenSSH_9.6p1 Ubuntu-3ubuntu13\r\n")

    def close(self):
        self.sock.close()
        for conn in self.accepted:
            conn.close()


@pytest.fixture
def quick(monkeypatch):
    monkeypatch.setattr(cluster, "HANDSHAKE_SECONDS", 1.0)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]  # free: nothing listens there once closed


def _sweep(folder: Path) -> Path:
    (folder / "scene.yaml").write_text(SCENE, encoding="utf-8")
    (folder / "sweep.yaml").write_text(SWEEP, encoding="utf-8")
    return folder / "sweep.yaml"


def _risk(folder: Path) -> Path:
    import yaml

    study = {"scene": str(REPO / "models" / "wu2021-pulse.yaml"), "measure": "pga",
             "design": {"kind": "msa", "levels": [0.2, 0.4]},
             "limits": {"drift": {"LS": 0.05}}, "hazard": {"power_law": {"k0": 1e-4, "k": 2.5}},
             "target": {"return_period": 475}, "bootstrap": 0}
    (folder / "study.yaml").write_text(yaml.safe_dump(study), encoding="utf-8")
    return folder / "study.yaml"


def _refused(capsys, command: str, path: Path, address: str) -> str:
    before = sorted(p.name for p in path.parent.iterdir())
    code = main([command, str(path), "-o", str(path.parent / "out.nc"), "-q",
                 "--scheduler", address])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and err.startswith(f"pframe: --scheduler {address}")
    assert len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in path.parent.iterdir()) == before  # no parts, lock, output
    return err


@pytest.mark.slow
@pytest.mark.parametrize("command", ["sweep", "risk"])
@pytest.mark.parametrize("mode, said", [
    ("silent", "does not answer as a Dask scheduler"),
    ("http", "does not answer as a Dask scheduler"),
    ("banner", "is not a Dask scheduler"),
])
def test_a_service_that_is_not_a_scheduler_is_named_as_such(tmp_path, capsys, quick, command,
                                                            mode, said):
    service = _Service(mode)
    try:
        path = _sweep(tmp_path) if command == "sweep" else _risk(tmp_path)
        err = _refused(capsys, command, path, f"tcp://127.0.0.1:{service.port}")
    finally:
        service.close()
    assert said in err and "memory" not in err


@pytest.mark.slow
@pytest.mark.parametrize("command", ["sweep", "risk"])
@pytest.mark.parametrize("address, said", [
    ("localhost", "has no port"),
    ("tcp://127.0.0.1:99999", "not a port number"),
    ("tcp://nosuch.invalid:8786", "not known here"),
    ("refused", "nothing listens"),
])
def test_a_wrong_address_leaves_nothing_behind(tmp_path, capsys, command, address, said):
    if address == "refused":
        address = f"tcp://127.0.0.1:{_free_port()}"
    path = _sweep(tmp_path) if command == "sweep" else _risk(tmp_path)
    assert said in _refused(capsys, command, path, address)


def test_an_empty_address_is_not_taken_for_none(tmp_path, capsys):
    _refused(capsys, "sweep", _sweep(tmp_path), "")
