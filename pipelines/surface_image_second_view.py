# script-version: 2
"""surface_image.py for a second camera in the same run (e.g. the mini-app's zoomed
view): Canopy runs each script file once per run, so a second view of the adaptive
surface needs a second file. This one runs surface_image.py's code with its own
settings (the same ones, see surface_image.py); give it another file_prefix, or the
two overwrite each other's images.
"""
import os

_here = os.path.dirname(os.path.abspath(__file__))
with open(os.path.join(_here, "surface_image.py")) as _source:
    exec(compile(_source.read(), os.path.join(_here, "surface_image.py"), "exec"))
