"""Validation against measurements: the model beside published bearing tests (issue 45).

    kinematics     the race-control kinematics: epicyclic cage speed, pure inner-/outer-race
                   control (Jones 1960; Harris & Kotzalas), the pure-rolling cage speed at any
                   pitch angle; the one copy of these relations
    series_file    the file format of a published test series (scenes/validation/<id>.toml):
                   its records, read through flexbearing.common.validation (one InputError line)
    brackets       the race-control brackets of a series' points and the bracket tables
    slip_rate      the paper's steady slip-rate test (Tables 4/5): the 15 cases run on the
                   dynamics until the cage speed settles (`flexbearing validate slip-rate`)
    series         every series against the model's steady states (`flexbearing validate series`,
                   docs/validation.md)

The command lines are in flexbearing.cli (run.py, validate_series.py): they parse and print, the
work is here.
"""
