"""A job's OpenEXR image as NumPy arrays, one per layer, read with the OpenEXR bindings."""

from __future__ import annotations

import dataclasses
import os
from typing import Any

import numpy as np
import OpenEXR

BEAUTY = "beauty"
"""The layer of the channels without a layer prefix (R, G, B, A)."""

_COMPONENT_ORDER = "RGBAXYZ"


@dataclasses.dataclass
class Image:
    """The final image of a job.

    layers maps a layer name to its pixels, rows from the top: "beauty" (R, G, B, A) as
    an array of shape (height, width, 4), "direct", "indirect", "caustic", "volume" and "albedo" as
    (height, width, 3) in R, G, B order, "normal" as (height, width, 3) in X, Y, Z order,
    a layer of one channel ("depth", from depth.Z) as (height, width); all float32.
    attributes holds the file's header (renderTime, samplesPerPixel, worldToCamera, ...).
    """

    width: int
    height: int
    layers: dict[str, np.ndarray]
    attributes: dict[str, Any]


def _component_key(component: str) -> tuple[int, str]:
    i = _COMPONENT_ORDER.find(component)
    return (i if len(component) == 1 and i >= 0 else len(_COMPONENT_ORDER), component)


def read_image(path: str | os.PathLike) -> Image:
    """Reads the first part of the EXR file at path, grouping channels by layer: the
    channel "indirect.R" is component R of layer "indirect"."""
    part = OpenEXR.File(os.fspath(path), separate_channels=True).parts[0]
    groups: dict[str, dict[str, np.ndarray]] = {}
    for name, channel in part.channels.items():
        layer, _, component = name.rpartition(".")
        groups.setdefault(layer or BEAUTY, {})[component] = channel.pixels
    layers = {}
    for layer, components in groups.items():
        ordered = [components[c] for c in sorted(components, key=_component_key)]
        layers[layer] = ordered[0] if len(ordered) == 1 else np.stack(ordered, axis=-1)
    return Image(width=part.width(), height=part.height(), layers=layers, attributes=dict(part.header))
