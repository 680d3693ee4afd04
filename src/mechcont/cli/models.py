"""``mechcont models``: the built-in models and shipped descriptions, with their variables."""

from __future__ import annotations

import json

import click

from ._app import cli


@cli.command("models")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
@click.argument("names", nargs=-1)
def models_command(as_json, names):
    """List models (or show NAMES) with states, parameters, defaults and units."""
    from ..models import load_model, model_names

    chosen = names or model_names()
    doc = []
    for name in chosen:
        s = load_model(name)
        doc.append({
            "name": name, "description": s.description, "equations": len(s.equations),
            "states": [{"name": v.name, "unit": v.unit, "description": v.description} for v in s.variables
                       if v.kind == "state"],
            "parameters": [{"name": v.name, "default": v.value, "unit": v.unit, "description": v.description}
                           for v in s.variables if v.kind == "parameter"],
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
