"""Measurements that write a docs page: effects, hair, materials, memory, passes, viewport."""
