"""Units at the border: the core works in metres, Blender in the scene's
units (`scene.unit_settings`: system, `scale_length`, length unit).

One Blender unit is `scale_length` metres (a millimetre scene for 3D
printing has `scale_length` 0.001 and length unit MILLIMETERS: one
Blender unit is one millimetre). Every length crosses here once:
- into the core: a property value, a location, a sketch point or a
  Blender matrix's translation times `metres_per_unit(scene)`;
- out of it: meshes, origins and lengths shown times `units_per_metre`.
Length properties are declared with `unit='LENGTH'`, so Blender shows
and parses them in the scene's unit system; their defaults are metres
turned into the scene's units when an operator runs (`fill_defaults`),
so a millimetre scene reads "100 mm", not "0.1 mm". Angles are Blender's
own (radians inside, degrees or radians shown as the scene says).
"""

from __future__ import annotations

import math

import bpy
import numpy as np


def snap32(v):
    """A float (or vector) Blender stored as float32, as the shortest
    decimal that rounds to the same float32: Blender keeps 0.012 as
    0.0120000001 (which the core would refuse at its bound 0.012) and a
    millimetre scene's scale 0.001 as 0.00100000005; the op log should
    read what the person typed."""
    if isinstance(v, (list, tuple)):
        return type(v)(snap32(x) for x in v)
    if isinstance(v, float) and math.isfinite(v):
        return float(str(np.float32(v)))
    return v


def metres_per_unit(scene: bpy.types.Scene | None) -> float:
    """Metres in one Blender unit of `scene`."""
    if scene is None:
        return 1.0
    scale = snap32(float(scene.unit_settings.scale_length))
    return scale if scale > 0.0 else 1.0


def units_per_metre(scene: bpy.types.Scene | None) -> float:
    """Blender units of `scene` in one metre."""
    return 1.0 / metres_per_unit(scene)


def to_metres(scene, value):
    """A length (or a sequence of them, nested) in Blender units, in metres."""
    k = metres_per_unit(scene)
    return _scaled(value, k)


def to_units(scene, value):
    """A length (or nested sequences) in metres, in Blender units."""
    return _scaled(value, units_per_metre(scene))


def _scaled(value, k: float):
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value) * k
    return [_scaled(v, k) for v in value]


# Blender's length units: metres in one, and the symbol shown.
LENGTH_UNITS = {
    "KILOMETERS": (1e3, "km"),
    "METERS": (1.0, "m"),
    "CENTIMETERS": (1e-2, "cm"),
    "MILLIMETERS": (1e-3, "mm"),
    "MICROMETERS": (1e-6, "µm"),
    "MILES": (1609.344, "mi"),
    "FEET": (0.3048, "'"),
    "INCHES": (0.0254, '"'),
    "THOU": (0.0000254, "thou"),
}


def length_text(scene, metres: float) -> str:
    """A length in metres as the scene shows lengths ("8 mm", "0.2 m"):
    in its length unit, or Blender's adaptive choice."""
    us = scene.unit_settings if scene is not None else None
    if us is None or us.system == "NONE":
        return f"{metres * units_per_metre(scene):g}"
    unit = LENGTH_UNITS.get(us.length_unit)
    if unit is not None:
        return f"{metres / unit[0]:.6g} {unit[1]}"
    try:
        return bpy.utils.units.to_string(
            us.system, "LENGTH", metres, precision=4, split_unit=False, compatible_unit=False
        )
    except (ValueError, TypeError):
        return f"{metres:g} m"


def fill_defaults(operator, scene, lengths: dict[str, float | tuple]) -> None:
    """Sets each length property of `operator` that the caller did not set
    to its default in metres (`lengths`: name -> metres) turned into the
    scene's units, so the values shown (the redo panel, F9) are the
    scene's and a later redo reads them back the same way."""
    props = operator.properties
    for name, metres in lengths.items():
        if not props.is_property_set(name):
            setattr(operator, name, to_units(scene, metres))
