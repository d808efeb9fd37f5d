# script-version: 2
"""A Catalyst script that loads the Canopy plugin and runs both filters on the
grid the simulation provides on channel 'input'; it writes what it got to the
file named by CANOPY_RESULT."""
import os

from paraview.simple import LoadPlugin, TrivialProducer

LoadPlugin(os.environ["CANOPY_PLUGIN"], remote=False, ns=globals())

producer = TrivialProducer(registrationName="input")
surface = CanopyAdaptiveSurface(Input=producer, ViewDependent=0)  # noqa: F821
selection = CanopyExtractSelection(  # noqa: F821
    Input=producer, SelectionMode="Locations",
    Locations=[0.1, 0.1, 0.0, 2.2, 1.6, 0.0, 3.0, 3.0, 0.0, 5.0, 5.0, 0.0])


def catalyst_execute(info):
    surface.UpdatePipeline()
    selection.UpdatePipeline()
    with open(os.environ["CANOPY_RESULT"], "w") as out:
        out.write("surface %d selection %d\n" % (surface.GetDataInformation().GetNumberOfCells(),
                                                selection.GetDataInformation().GetNumberOfCells()))
