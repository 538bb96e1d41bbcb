"""Measurements that write a docs page (effects, hair, materials, memory, passes, viewport,
world light), and the cost of noise-driven sampling's rounds."""
