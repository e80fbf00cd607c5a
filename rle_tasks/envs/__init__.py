"""Environments shared by two or more families (content, not mechanism: that lives in ``rle_design``)."""
