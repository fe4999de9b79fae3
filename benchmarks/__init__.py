"""Speed benchmarks: ``python -m benchmarks [NAME...]``.

Each benchmark times gaitgram and a baseline on the same input in the same run,
and prints both with their ratio, so figures compare across machines.
"""
