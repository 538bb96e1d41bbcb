"""The performance suite behind scripts/bench_performance.py (issue 7): plan (what a run
measures), measure (the Blender processes that measure it), figures (derived figures
and the targets), page (docs/PERFORMANCE.md), plots (its plots)."""
