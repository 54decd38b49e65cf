"""Exceptions that mean "bad usage or bad input" (exit code 2 on the command line)."""


class UserInputError(Exception):
    """Bad usage or bad input: a config, an override, a file or a command-line value.

    The message is one sentence naming what is wrong and where. The command line prints it
    and exits with code 2; nothing already stored is changed.
    """


class ConfigError(UserInputError):
    """A study or group config is malformed: unknown key, wrong type or out-of-range value."""


class StudyNotRunnableError(UserInputError):
    """The study's trial kind is not implemented yet, so the study cannot run."""


class DamagedRunError(UserInputError):
    """A stored file of a run fails full verification (a damaged page, footer or checksum).

    Reading a run never changes it: the report and the status refuse such a run, naming it and
    the file; resuming the run quarantines the file and runs its trials again.

    Attributes
    ----------
    what : str
        What is wrong, without the run's path or the advice ("has a duplicate file ..."), for a
        page that names the run itself.
    """

    def __init__(self, message: str, what: str | None = None):
        super().__init__(message)
        self.what = what or message


class MissingSourceRunError(UserInputError):
    """A study whose design is read from another study's records, before that run exists.

    Attributes
    ----------
    source : str
        The ``study`` (or ``study --run name``) to run first.
    """

    def __init__(self, message: str, source: str):
        super().__init__(message)
        self.source = source
