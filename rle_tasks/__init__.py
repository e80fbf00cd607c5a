"""RLE-Bench tasks: the 51 task instances of the paper, their verifiers and the shared runtime."""
