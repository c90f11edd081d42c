"""Generates the renderfarm.v1 protobuf and gRPC modules from the repository's proto/
folder while a wheel is built, so that they are never committed nor copied by hand. The
rest of the metadata is in pyproject.toml."""

import pathlib
import shutil
import sys

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = pathlib.Path(__file__).resolve().parent
PROTO_ROOT = HERE.parent.parent / "proto"


class BuildWithStubs(build_py):
    """build_py, then grpc_tools.protoc over proto/renderfarm/v1 into the build folder:
    renderfarm/v1/*_pb2.py with their .pyi type stubs and *_pb2_grpc.py."""

    def run(self) -> None:
        super().run()
        from grpc_tools import protoc  # a build requirement (pyproject.toml)
        import importlib.resources

        protos = sorted(PROTO_ROOT.glob("renderfarm/v1/*.proto"))
        if not protos:
            sys.exit(f"photonfarm: no .proto files under {PROTO_ROOT}: build from a photonfarm "
                     "checkout (pip install ./client/python), where proto/ is two folders up")
        out = pathlib.Path(self.build_lib)
        shutil.rmtree(out / "renderfarm", ignore_errors=True)  # modules of removed .proto files
        well_known = importlib.resources.files("grpc_tools") / "_proto"
        args = ["grpc_tools.protoc", f"-I{PROTO_ROOT}", f"-I{well_known}",
                f"--python_out={out}", f"--pyi_out={out}", f"--grpc_python_out={out}",
                *map(str, protos)]
        if protoc.main(args) != 0:
            sys.exit("photonfarm: grpc_tools.protoc failed on " + " ".join(map(str, protos)))
        for pkg in (out / "renderfarm", out / "renderfarm" / "v1"):
            (pkg / "__init__.py").touch()


setup(cmdclass={"build_py": BuildWithStubs})
