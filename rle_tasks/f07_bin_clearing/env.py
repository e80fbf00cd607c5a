"""The environment definition shared by ``rle dev`` (metered session) and the verifier (episodes)."""

from rle_tasks.f07_bin_clearing.public.env import EPISODE_S, BinClearingEnv, NestLogic, make_env
from rle_tasks.f07_bin_clearing.public.events import EventCounter

__all__ = ["EPISODE_S", "BinClearingEnv", "EventCounter", "NestLogic", "make_env"]
