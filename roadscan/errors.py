"""Errors that carry a file name and a one-line explanation (shown to users as-is)."""

__all__ = ["InputError"]


class InputError(ValueError):
    """Bad input: ``str(err)`` is one line naming the file and the problem."""

    def __init__(self, path, problem):
        self.path = str(path) if path is not None else None
        self.problem = str(problem).strip().splitlines()[0] if str(problem).strip() else "invalid input"
        super().__init__(f"{self.path}: {self.problem}" if self.path else self.problem)
