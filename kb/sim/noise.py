"""The noise of the simulated pose sensor: what it gets wrong, look by look.

What a sensor's accuracy is (:class:`~kb.cells.accuracy.SensorAccuracy`: position,
orientation and bias sigmas, misdetection and misclassification rates; read from the state's
``ktw:PoseSensor`` or ``--sensor-noise``) is owned below the executor, in
:mod:`kb.cells.accuracy`, because the executor assumes it of any cell. The simulator draws its
sensor's errors from the same values: :class:`kb.sim.sensor.Sensor` adds them to what it
reports (Gaussian position and orientation noise per look from the cell's seeded generator, a
per-object bias drawn once per object, objects not reported, objects reported with another
SKU), never to the ground truth.

``SensorNoise`` is the accuracy type under the name the simulator has always used for it (the
same class); the other names are re-exported for the same reason.
"""

from __future__ import annotations

from kb.cells.accuracy import ANGLES, KEYS, LENGTHS, PROPERTIES, SENSOR_OF, SensorAccuracy

#: the noise a simulated sensor adds: the accuracy it is declared to have (the same class)
SensorNoise = SensorAccuracy

__all__ = ["ANGLES", "KEYS", "LENGTHS", "PROPERTIES", "SENSOR_OF", "SensorAccuracy", "SensorNoise"]
