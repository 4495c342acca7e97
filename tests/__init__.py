"""The tests, one package per layer of the harness (tests/<layer>/), helpers in tests/support."""
