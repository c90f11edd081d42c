"""What the SDK decides before any call: where a token may go, which files a scene may
name, how an EXR's channels become layers."""

from __future__ import annotations

import json

import grpc
import numpy as np
import OpenEXR
import pytest

import photonfarm
from photonfarm.connection import is_loopback, replica_target
from photonfarm.exr import read_image


@pytest.mark.parametrize("address, loopback", [
    ("localhost:7070", True), ("render.localhost:7070", True), ("127.0.0.1:7070", True),
    ("127.9.9.9:1", True), ("[::1]:7070", True), ("dns:///localhost:7070", True), ("unix:/tmp/farm.sock", True),
    ("farm.example.invalid:7070", False), ("192.0.2.1:7070", False), ("[2001:db8::1]:7070", False),
    ("localhost.example.invalid:7070", False), ("127.0.0.1:1,[::1]:2", True), ("127.0.0.1:1,192.0.2.1:2", False),
])
def test_is_loopback(address, loopback):
    assert is_loopback(address) == loopback


def test_replicas_are_a_list_target_of_ip_literals_spread_round_robin():
    assert replica_target("coordinator:7070") == ("coordinator:7070", [])
    assert replica_target("10.0.0.1:7070,10.0.0.2:7070") == (
        "ipv4:10.0.0.1:7070,10.0.0.2:7070", [("grpc.lb_policy_name", "round_robin"), ("grpc.default_authority", "10.0.0.1:7070")])
    assert replica_target("[::1]:1,[fd00::2]:2")[0] == "ipv6:[::1]:1,[fd00::2]:2"


@pytest.mark.parametrize("address, says", [
    ("a.example:1,b.example:1", "must be IP literals"), ("10.0.0.1:1,[::1]:1", "all IPv4 or all IPv6"),
    ("10.0.0.1:1,", '"" in'), ("10.0.0.1:1,10.0.0.1:1", "twice"), ("10.0.0.1:1,10.0.0.2:0", "is not HOST:PORT"),
])
def test_a_list_grpc_cannot_reach_is_refused_saying_why(address, says):
    with pytest.raises(photonfarm.FarmError) as e:
        photonfarm.Client(address, tls=False)
    assert e.value.code == grpc.StatusCode.INVALID_ARGUMENT and says in str(e.value)


def test_a_token_is_not_sent_in_plaintext_to_another_machine():
    with pytest.raises(photonfarm.FarmError) as e:
        photonfarm.Client("farm.example.invalid:7070", token="secret", tls=False)
    assert e.value.code == grpc.StatusCode.FAILED_PRECONDITION and "allow_plaintext_token" in e.value.hint
    photonfarm.Client("farm.example.invalid:7070", token="secret", tls=False, allow_plaintext_token=True).close()


def test_an_unreadable_ca_file_is_refused(tmp_path):
    (tmp_path / "ca.pem").write_text("not a certificate\n")
    for ca, says in [(tmp_path / "ca.pem", "no PEM certificate"), (tmp_path / "none.pem", "No such file")]:
        with pytest.raises(photonfarm.FarmError, match=says):
            photonfarm.Client("localhost:7070", tls=str(ca))


def scene_naming(path: str) -> dict:
    return {"shapes": [{"material": "m", "mesh": {"path": path}}]}


def test_files_outside_the_asset_root_are_refused_before_any_call(tmp_path, unused_address):
    (tmp_path / "root").mkdir()
    (tmp_path / "secret.obj").write_text("v 0 0 0\n")
    (tmp_path / "root" / "link.obj").symlink_to(tmp_path / "secret.obj")
    scene = tmp_path / "root" / "scene.json"
    with photonfarm.Client(unused_address) as c:
        for path, says in [("../secret.obj", "outside the asset root"), ("link.obj", "symbolic link"),
                           ("/dev/zero", "outside the asset root")]:
            scene.write_text(json.dumps(scene_naming(path)))
            with pytest.raises(photonfarm.FarmError, match=says) as e:
                c.submit(scene)
            assert e.value.code == grpc.StatusCode.INVALID_ARGUMENT and e.value.field == "shapes[0].mesh.path"
        with pytest.raises(photonfarm.FarmError, match="not a regular file") as e:
            c.submit(scene_naming("/dev/zero"), asset_root="/")
        with pytest.raises(photonfarm.FarmError, match=r"digest.*set only one") as e:
            c.submit({"shapes": [{"material": "m", "mesh": {"path": "a.obj", "digest": "sha256:" + "0" * 64}}]},
                     {"a.obj": b"v 0 0 0\n"})
        assert e.value.field == "shapes[0].mesh.digest"
        with pytest.raises(photonfarm.FarmError, match="widht") as e:
            c.submit({"film": {"widht": 4}})


def test_exr_channels_become_layers_in_component_order(tmp_path):
    h, w = 3, 5
    values = {name: np.full((h, w), i, dtype=np.float32) for i, name in enumerate(
        ["A", "B", "G", "R", "depth.Z", "normal.X", "normal.Y", "normal.Z", "indirect.B", "indirect.G", "indirect.R"])}
    values["R"] = np.arange(h * w, dtype=np.float32).reshape(h, w)  # rows from the top
    path = tmp_path / "image.exr"
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                 {k: OpenEXR.Channel(k, v) for k, v in values.items()}).write(str(path))
    image = read_image(path)
    assert (image.width, image.height) == (w, h)
    assert image.layers.keys() == {"beauty", "depth", "normal", "indirect"}
    np.testing.assert_array_equal(image.layers["beauty"][0, 1], [1, 2, 1, 0])  # R G B A
    np.testing.assert_array_equal(image.layers["beauty"][2, 4, 0], 14)
    np.testing.assert_array_equal(image.layers["normal"][1, 1], [5, 6, 7])  # X Y Z
    np.testing.assert_array_equal(image.layers["indirect"][0, 0], [10, 9, 8])  # R G B
    assert image.layers["depth"].shape == (h, w) and image.layers["depth"][0, 0] == 4
