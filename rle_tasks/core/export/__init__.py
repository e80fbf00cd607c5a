"""Exports of the benchmark to evaluation harnesses (``harbor``)."""
