"""Offscreen PNG renders and meshcat previews of MJCF designs."""
