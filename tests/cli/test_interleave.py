"""lib/bench/interleave.py: two fake benchmark programs take turns in alternating order, and the
printed ratios are the medians' ratios. Run: /usr/bin/python3 tests/cli/test_interleave.py"""
import pathlib
import subprocess
import sys
import tempfile
import unittest

SCRIPT = pathlib.Path(__file__).resolve().parents[2] / "lib" / "bench" / "interleave.py"

# A stand-in for billiard_bench: logs its name and arguments, prints its table (the rate of each
# run read from RATES, one per call), and a course row that must not count.
FAKE = """#!/bin/sh
echo "{name} $*" >> "{log}"
count=$(grep -c "^{name} " "{log}")
rate=$(sed -n "${{count}}p" "{rates}")
echo "engine   container         N     eta    g   collisions/s cross/coll stale/coll bytes/disc  setup s"
echo "engine   box            1000   0.100    0        $rate      2.375      0.107        351     0.00"
echo "engine   table         10000   0.500    1        2000000      0.409      0.168        353     0.00"
echo "course   table           100   0.100    0          49079      0.000      0.000          0     0.00"
"""


class Interleave(unittest.TestCase):
    def fake(self, folder, name, rates):
        (folder / f"{name}.rates").write_text("\n".join(str(r) for r in rates) + "\n")
        program = folder / name
        program.write_text(FAKE.format(name=name, log=folder / "log", rates=folder / f"{name}.rates"))
        program.chmod(0o755)
        return program

    def test_turns_alternate_and_ratios_are_of_the_medians(self):
        with tempfile.TemporaryDirectory() as folder:
            folder = pathlib.Path(folder)
            before = self.fake(folder, "before", [1000, 3000, 2000, 9000])   # median 2500
            after = self.fake(folder, "after", [2750, 2750, 100, 9999])      # median 2750
            done = subprocess.run([sys.executable, str(SCRIPT), str(before), str(after), "--rounds", "4", "--",
                                   "--n", "1000", "--repeats", "1"], capture_output=True, text=True)
            self.assertEqual(done.returncode, 0, done.stderr)
            calls = (folder / "log").read_text().split("\n")[:-1]
            self.assertEqual([c.split()[0] for c in calls], ["before", "after", "after", "before"] * 2)
            self.assertTrue(all(c.endswith("--n 1000 --repeats 1") for c in calls), calls)
            box = next(line for line in done.stdout.splitlines() if line.startswith("box"))
            self.assertEqual(box.split()[-3:], ["2500", "2750", "1.100"])
            self.assertNotIn("course", done.stdout)
            self.assertIn("median 1.050 over 2 rows", done.stdout)  # (1.100 and 1.000)

    def test_a_program_without_engine_rows_is_one_clear_error(self):
        with tempfile.TemporaryDirectory() as folder:
            folder = pathlib.Path(folder)
            broken = folder / "broken"
            broken.write_text("#!/bin/sh\necho 'billiard_bench: --n takes whole numbers' >&2\nexit 2\n")
            broken.chmod(0o755)
            done = subprocess.run([sys.executable, str(SCRIPT), str(broken), str(broken), "--", "--n", "0"],
                                  capture_output=True, text=True)
            self.assertNotEqual(done.returncode, 0)
            self.assertIn("printed no engine rows", done.stderr)
            self.assertIn("--n takes whole numbers", done.stderr)


if __name__ == "__main__":
    unittest.main()
