"""The language server for ``.mission`` files, built on the parser, the checker and the
world loader (``robocop-mission lsp``)."""
