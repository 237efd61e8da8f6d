"""Errors that the command line turns into exit codes (2: case or folder, 1: computation)."""


class CaseError(ValueError):
    """The case is invalid. `key` names the offending key path."""

    def __init__(self, key: str, reason: str):
        self.key = key
        self.reason = reason
        super().__init__(f"{key}: {reason}")

    def __reduce__(self):   # pickled as it was made
        return type(self), (self.key, self.reason)


class ComputationError(RuntimeError):
    """The computation failed; what was finished is kept on disk."""


class WriteError(ComputationError):
    """A file of the result cannot be written (the disk is full, the folder
    became read-only or unwritable, the file's name is taken by a folder):
    `path` names the file, `reason` says why (the system's words). A run
    that meets it fails with "failed: cannot write <path>: <reason>"."""

    def __init__(self, path, reason: str):
        self.path = str(path)
        self.reason = reason
        super().__init__(f"cannot write {self.path}: {reason}")

    def __reduce__(self):   # pickled as it was made (parallel.on_root sends it to every rank)
        return type(self), (self.path, self.reason)


class FolderError(ValueError):
    """A folder given on the command line cannot be used: an output folder
    that cannot be written or holds a previous result, or a folder that is
    not a wingcrack result. `path` names it; the CLI exits with 2."""

    def __init__(self, path, reason: str):
        self.path = str(path)
        self.reason = reason
        super().__init__(f"{self.path}: {reason}")

    def __reduce__(self):   # pickled as it was made (a picture drawn in another process raises it here)
        return type(self), (self.path, self.reason)


class Collapse(ComputationError):
    """A piece that only contact holds cannot be held: the body is a
    mechanism under its load (the message names the piece and its motion).
    A run that reaches it has ended its loading path: it stops there."""
