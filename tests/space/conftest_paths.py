from pathlib import Path

INSTANCES = Path(__file__).resolve().parents[2] / "instances"
