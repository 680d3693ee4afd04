"""Imports every command module so that each registers itself on the group (``_app.COMMAND_MODULES``)."""
from ._app import _register

_register()
