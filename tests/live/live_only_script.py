# script-version: 2
"""A pipeline script of a user's own whose only consumer is a Catalyst Live
viewer: an adaptive surface of the grid at full resolution, no extractor, no
catalyst_execute, Live turned on in its options as ParaView's documentation
shows. With Live on, it runs at the steps of its Live trigger (every step here)
and a viewer receives "CanopyAdaptiveSurface1" (tests/live/live_only_check.py).
The viewer's address: LIVE_URL in the environment (host:port)."""
import os

from paraview import catalyst
from paraview.simple import LoadPlugin, TrivialProducer

LoadPlugin(os.environ["CANOPY_PLUGIN"], remote=False, ns=globals())

grid = TrivialProducer(registrationName="grid")
surface = CanopyAdaptiveSurface(Input=grid, ViewDependent=0)  # noqa: F821

options = catalyst.Options()
options.EnableCatalystLive = 1
options.CatalystLiveURL = os.environ["LIVE_URL"]
