# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line's two kinds of failure; every message is written for the user."""


class UsageError(Exception):
    """A bad command line (one message per problem): nothing is done, exit status 2."""

    def __init__(self, *messages):
        super().__init__("; ".join(messages))
        self.messages = list(messages)


class InputError(Exception):
    """An input that cannot be processed: that input fails, the others are still done."""
