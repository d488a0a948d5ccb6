import subprocess
import sys


def test_cli_help_lists_commands_without_loading_fe_stack():
    code = ("import sys; from coupling.cli import build_parser; build_parser(); "
            "print('dolfinx' in sys.modules, 'gmsh' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]
