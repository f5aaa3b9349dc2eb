"""The width stations: 5 %, 10 %, … 95 % of body length from the rostrum tip (DESIGN.md §7).

The one definition of the station grid for the model, the annotations, the measurements and
the file formats. Imports nothing from core, so that every layer can import it.
"""

import numpy as np

NUM_STATIONS = 19
STATION_FRACTIONS = np.arange(1, NUM_STATIONS + 1) * 0.05  # fractions of body length
# Percent of body length, rounded so that they compare equal to the 5, 10, … of the files
STATION_PCT = np.round(STATION_FRACTIONS * 100, 6)
STATION_FRACTIONS.flags.writeable = False
STATION_PCT.flags.writeable = False
