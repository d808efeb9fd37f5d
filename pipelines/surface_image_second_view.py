# script-version: 2
# canopy-renders: yes
"""surface_image.py for a second camera in the same run (e.g. the mini-app's zoomed
view): Canopy runs each script file once per run, so a second view of the adaptive
surface needs a second file. This one builds surface_image.py's pipeline
(canopy_catalyst.SurfaceImage) with its own settings (the same ones, see
surface_image.py); give it another file_prefix, or the two overwrite each other's
images.
"""
import canopy_catalyst as canopy

settings = canopy.settings(**dict(canopy.SURFACE_DEFAULTS, file_prefix="surface"))
image = canopy.SurfaceImage(settings)
options = image.options


def RequestDataDescription(datadescription):
    image.request_fields(datadescription)


def catalyst_execute(info):
    # Collective (bounds and colour ranges agree over ranks): every rank calls it.
    image.execute(info)
