"""Public modules of 09-gello: laid into the agent workspace as they are; they import only ``rle_design``."""
