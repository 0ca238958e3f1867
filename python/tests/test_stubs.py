"""The type stubs editors read say what the module does: Pipeline's keywords and their defaults."""

import ast
import re
from pathlib import Path

import iilfm


def stub_pipeline_defaults():
    stub = ast.parse((Path(iilfm.__file__).parent / "_iilfm.pyi").read_text())
    pipeline = next(n for n in stub.body if isinstance(n, ast.ClassDef) and n.name == "Pipeline")
    init = next(n for n in pipeline.body if isinstance(n, ast.FunctionDef) and n.name == "__init__")
    args = init.args
    positional = args.args[1:]  # without self
    defaults = dict(zip([a.arg for a in positional[len(positional) - len(args.defaults):]],
                        args.defaults))
    defaults.update({a.arg: d for a, d in zip(args.kwonlyargs, args.kw_defaults)})
    return {name: ast.literal_eval(d) for name, d in defaults.items()
            if not (isinstance(d, ast.Constant) and d.value is Ellipsis)}


def runtime_pipeline_defaults():
    # pybind11's signature line: "__init__(self: ..., name: type = default, ...) -> None".
    signature = iilfm.Pipeline.__init__.__doc__.splitlines()[0]
    return {name: ast.literal_eval(value)
            for name, value in re.findall(r"(\w+): [\w.\[\], ]+? = ([^,)]+)", signature)}


def test_pipeline_stub_has_every_keyword_with_its_default():
    stub, runtime = stub_pipeline_defaults(), runtime_pipeline_defaults()
    assert len(runtime) > 20
    missing = set(runtime) - set(stub) - {"markers"}  # the stub writes markers' default as ...
    assert not missing, missing
    for name, value in stub.items():
        assert name in runtime, name
        assert runtime[name] == value, (name, runtime[name], value)
