"""world.view(): the live view of a World stepped from Python (docs/viewer.md "Live view").

A viewer here is a bare WebSocket client written for the test (RFC 6455's handshake
and frames, nothing more): it reads the frames the steps send and sends a drag."""

import base64
import json
import os
import socket
import struct
import urllib.request

import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(PYTHONPATH=build/python)")


def _view_or_skip(world, **kwargs):
    try:
        return world.view(**kwargs)
    except RuntimeError as e:
        if "not built" in str(e):
            pytest.skip(str(e))
        raise


class _Viewer:
    """A WebSocket client on the live view's /ws."""

    def __init__(self, url):
        host, port = url.split("//")[1].rstrip("/").split(":")
        self.sock = socket.create_connection((host, int(port)), timeout=10)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET /ws HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                           "Sec-WebSocket-Version: 13\r\n\r\n").encode())
        answer = b""
        while b"\r\n\r\n" not in answer:
            answer += self.sock.recv(1)
        assert answer.startswith(b"HTTP/1.1 101"), answer
        # The server's hello: from here on this viewer counts (frames are sent to it).
        assert self.message() == (1, b'{"type":"hello"}')

    def _exactly(self, n):
        data = b""
        while len(data) < n:
            chunk = self.sock.recv(n - len(data))
            assert chunk, "closed"
            data += chunk
        return data

    def message(self):
        """(opcode, payload) of the next message (unfragmented, as the server sends)."""
        first, second = self._exactly(2)
        length = second & 0x7F
        if length == 126:
            length = struct.unpack(">H", self._exactly(2))[0]
        elif length == 127:
            length = struct.unpack(">Q", self._exactly(8))[0]
        return first & 0x0F, self._exactly(length)

    def frame(self):
        """The next binary message: (header of 8 doubles, particle count)."""
        while True:
            opcode, payload = self.message()
            if opcode == 2:
                return struct.unpack("<8d", payload[:64]), (len(payload) - 64) // 12

    def send(self, message):
        payload = json.dumps(message).encode()
        mask = os.urandom(4)
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        assert len(payload) < 126
        self.sock.sendall(bytes([0x81, 0x80 | len(payload)]) + mask + masked)


def test_view_serves_the_page_and_changes_nothing_without_a_drag(scenes):
    plain = robophi.World(robophi.load(scenes / "pendulum.json"))
    watched = robophi.World(robophi.load(scenes / "pendulum.json"))
    url = _view_or_skip(watched, port=0, speed=0)
    assert url.startswith("http://127.0.0.1:")
    page = urllib.request.urlopen(url, timeout=10).read().decode()
    assert '"live":{"socket":"/ws"}' in page
    viewer = _Viewer(url)
    for _ in range(300):
        plain.advance()
        watched.advance()
    assert watched.hash() == plain.hash()
    header, count = viewer.frame()
    assert count == watched.particle_count and 0 <= header[0] <= watched.time
    watched.close_view()


def test_a_drag_from_the_viewer_is_external_work(scenes):
    world = robophi.World(robophi.load(scenes / "pendulum.json"))
    url = _view_or_skip(world, port=0, speed=1)  # real time: the messages are read meanwhile
    viewer = _Viewer(url)
    world.advance()  # (the server has the socket once a frame went out)
    viewer.frame()
    viewer.send({"type": "drag", "particle": 3, "target": [0, 0, 2.6]})
    while world.time < 1.0:  # 1 s of wall time
        world.advance()
    header, _ = viewer.frame()
    while header[6] == 0.0:  # (frames sent before the drag came)
        header, _ = viewer.frame()
    # In each frame, the drag's work is the world's external work (nothing else works on it).
    assert header[6] > 0.0  # pulled from rest at the side towards the top
    assert header[5] == pytest.approx(header[6], rel=1e-6)
    assert world.energy.external > 0.0
    world.close_view()
