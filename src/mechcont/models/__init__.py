"""Built-in models: the paper's own formulations, kept as references, and the resolver
that also accepts mechanism description files."""

from ._registry import BUILTIN_MODELS, ModelSummary, describe_model, load_model, model_at, model_from_text, model_names
from .overcentre import build_overcentre

__all__ = ["build_overcentre", "load_model", "model_at", "model_from_text", "model_names", "describe_model",
           "ModelSummary", "BUILTIN_MODELS"]
