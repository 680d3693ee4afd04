"""``mechcont models``: the built-in models and shipped descriptions, with their variables."""

from __future__ import annotations

import json
from typing import Any

import click

from ._app import cli


@cli.command("models")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
@click.argument("names", nargs=-1)
def models_command(as_json: bool, names: tuple[str, ...]) -> None:
    """List models (or show NAMES) with states, parameters, defaults and units."""
    from ..models import describe_model, model_names

    chosen = names or model_names()
    doc: list[dict[str, Any]] = []
    for name in chosen:
        s = describe_model(name)  # from the registry and the descriptions: nothing is compiled
        doc.append({
            "name": name, "description": s.description, "equations": s.n_equations,
            "states": [{"name": n, "unit": u, "description": d} for n, u, d in s.states],
            "parameters": [{"name": n, "default": v, "unit": u, "description": d} for n, v, u, d in s.parameters],
        })
    if as_json:
        click.echo(json.dumps(doc, indent=1))
        return
    for m in doc:
        click.echo(f"{m['name']}: {m['description']} ({m['equations']} equations)")
        click.echo("  states: " + ", ".join(f"{v['name']} [{v['unit']}]" for v in m["states"]))
        click.echo("  parameters:")
        for p in m["parameters"]:
            click.echo(f"    {p['name']:<10} = {p['default']:<12.6g} {p['unit']:<8} {p['description']}")
