"""The performance suite (issue 7): docs/PERFORMANCE.md and the Blender runs it makes.

suite (the bench-performance verb), plan (what a run measures), measure (the Blender
processes that measure it), figures (derived figures and the targets), page
(docs/PERFORMANCE.md), plots (its plots); the verbs it runs in Blender: scenes, render,
raw_embree, povray_render."""
