"""The comparison galleries: Whitted beside Cycles (lights, materials, distributed effects)."""
