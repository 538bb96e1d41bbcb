"""Where the trace time goes."""
