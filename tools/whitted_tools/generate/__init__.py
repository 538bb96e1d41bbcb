"""Generated sources: tables the native code compiles in, made from third-party data."""
