"""The physical pocket cube of task 03-pocket-cube: model, move model, state reading, distances, score."""
