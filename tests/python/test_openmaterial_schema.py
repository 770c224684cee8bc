"""[python] `retroprism export --format openmaterial` against the format's published JSON schemas
(ASAM OpenMATERIAL 3D 1.0.0, tests/data/openmaterial/, validated with python3-jsonschema)."""
import json
import os
import subprocess

import jsonschema
import pytest

CLI = os.environ["RETROPRISM_CLI"]
ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
PLATE = os.path.join(ROOT, "examples", "materials", "microprismatic_160um.json")
SCHEMAS = os.path.join(ROOT, "tests", "data", "openmaterial")


def schema(name):
    with open(os.path.join(SCHEMAS, name)) as f:
        return json.load(f)


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    out = tmp_path_factory.mktemp("openmaterial")
    subprocess.run([CLI, "export", "--format", "openmaterial", "--out", str(out), "--json", PLATE,
                    "--name", "plate", "--wavelength", "905,1550"], check=True,
                   capture_output=True)
    with open(out / "plate.xomp") as f:
        material = json.load(f)
    with open(out / "plate_brdf.xompt") as f:
        table = json.load(f)
    return material, table


def test_the_material_file_follows_its_schema(exported):
    material, _ = exported
    jsonschema.Draft7Validator(schema("material_schema.json")).validate(material)
    assert material["materialProperties"]["brdfUris"] == ["plate_brdf.xompt"]


def test_the_brdf_table_follows_its_schema(exported):
    _, table = exported
    jsonschema.Draft7Validator(schema("material_brdf_schema.json")).validate(table)
    rows = table["brdf"]["lookupTable"]
    assert rows == sorted(rows)


def test_the_schema_rejects_what_the_reader_rejects(exported):
    # The validation is not vacuous: an angle beyond pi/2 fails it.
    _, table = exported
    broken = json.loads(json.dumps(table))
    broken["brdf"]["lookupTable"][5][2] = 2.0
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.Draft7Validator(schema("material_brdf_schema.json")).validate(broken)
