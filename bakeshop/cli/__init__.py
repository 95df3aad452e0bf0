"""The ``bakeshop`` command: argument parsing, progress and messages. No algorithm lives here."""
