"""Errors that the command line turns into exit codes (2: case, 1: computation)."""


class CaseError(ValueError):
    """The case is invalid. `key` names the offending key path."""

    def __init__(self, key: str, reason: str):
        self.key = key
        self.reason = reason
        super().__init__(f"{key}: {reason}")


class ComputationError(RuntimeError):
    """The computation failed; what was finished is kept on disk."""
