"""The exceptions of orcs_client. Each carries one line that says what went wrong and where."""


class OrcsClientError(Exception):
    """Base of every error orcs_client raises on purpose."""


class SetupError(OrcsClientError):
    """Something orcs_client needs is missing: the generated protobuf modules, pyzmq, or the orcs-batch program."""


class ScenarioError(OrcsClientError):
    """A scenario file (or a file it references) is bad; the message names the file and the field."""


class BrokerError(OrcsClientError):
    """No broker answering within the connect timeout, the broker lost for good, or a submission it rejected.

    Like the C++ BatchClientError: once a client has raised one, every later call raises it again; make a new
    client.
    """


class ResultTimeout(OrcsClientError):
    """No result arrived within the time the caller gave; the batch goes on and can be waited for again."""
