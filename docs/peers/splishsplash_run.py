"""Times SPlisHSPlasH's DFSPH on the dambreak32k scene (docs/peers/README.md).

Usage: python splishsplash_run.py SCENE.json
"""
import sys
import time

import pysplishsplash as sph

base = sph.Exec.SimulatorBase()
base.init(sceneFile=sys.argv[1], useGui=False, useCache=False, outputDir="/tmp/splishsplash_out",
          initialPause=False, stopAt=0.5)
base.initSimulation()
print("fluid particles", sph.Simulation.getCurrent().getFluidModel(0).numActiveParticles())
start = time.time()
base.runSimulation()
print(f"run {time.time() - start:.2f} s wall, simulated {sph.TimeManager.getCurrent().getTime():.4f} s")
base.cleanup()
