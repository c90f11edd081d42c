"""Zips the add-on for Blender's installer: `python3 client/blender/package.py OUT.zip`
(make blender-addon). The zip holds photonfarm_blender/ with its Python files and
blender_manifest.toml, so it installs both as a legacy add-on (Install from Disk under
Add-ons) and as an extension (Blender 4.2 and later)."""

import os
import sys
import zipfile

ADDON = os.path.join(os.path.dirname(os.path.abspath(__file__)), "photonfarm_blender")


def build(out_path):
    with zipfile.ZipFile(out_path, "w", zipfile.ZIP_DEFLATED) as z:
        for name in sorted(os.listdir(ADDON)):
            if name.endswith((".py", ".toml")):
                z.write(os.path.join(ADDON, name), f"photonfarm_blender/{name}")
    return out_path


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: package.py OUT.zip")
    print(build(sys.argv[1]))
