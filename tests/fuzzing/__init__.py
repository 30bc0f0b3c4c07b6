"""Hostile-input fuzzing of the public API, shared by tests/test_fuzz_api.py and benchmarks/fuzz.py."""
