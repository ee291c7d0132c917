"""Where the shared references live: ``shared/`` beside the repository checkout (as on developer machines and CI)."""
from pathlib import Path

SHARED_REFERENCE = Path(__file__).resolve().parents[2] / "shared" / "reference"
PROFILES_DIR = SHARED_REFERENCE / "profiles"
HERTZ_M_N_TABLE = SHARED_REFERENCE / "hertz_m_n.csv"

if not SHARED_REFERENCE.is_dir():
    raise FileNotFoundError(f"shared references not found at {SHARED_REFERENCE}: the tests compare against them, "
                            "so shared/ must sit beside the repository checkout")
