"""Checks run by hand: image hashes, the fuzz tests, two kernels or two builds compared."""
