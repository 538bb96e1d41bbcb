"""The Rendered viewport: the view's camera (camera.py), the session that syncs,
restarts and polls the progressive job (session.py), the GPU texture it draws
(display.py) and the event log tests and benchmarks read (log.py)."""
