"""Loads one of the add-on's files by path, without its package: photonfarm_blender/__init__.py
imports bpy, and the pure modules are tested without Blender."""

import importlib.util
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def load(relative):
    name = "photonfarm_" + os.path.splitext(os.path.basename(relative))[0]
    spec = importlib.util.spec_from_file_location(name, os.path.join(ROOT, relative))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
