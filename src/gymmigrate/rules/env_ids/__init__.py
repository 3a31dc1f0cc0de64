"""Environment ids, third-party registration and the registry API (GM106, GM802-GM806).

    catalog.py         what retired, Atari and removed-family ids become (tables, no syntax)
    syntax.py          which calls take an id, which literals can be rewritten, the registry
    ids.py             GM803-GM805 id strings and GM106 registration imports   [20]
    id_sites.py        where ids are: the literals id-taking calls receive, directly or not
    handed_on_ids.py   ids the project's code makes: passed on, made elsewhere, retired
    id_literals.py     IdSite, the literal a name holds, which calls take an id
    atari_evidence.py  Atari envs made without a literal id (GM106's ale_py import)
    registry.py        GM802 registry API, GM806 EnvSpec attributes, GM807/GM808/GM810 [21]
    env_specs.py       which expressions are an EnvSpec (GM806's receivers)
    registry_edits.py  registry.py's CST edits: spec keywords, checker off, entry points
"""

from gymmigrate.rules.env_ids import ids, registry  # noqa: F401  (imported to register their families)
from gymmigrate.rules.env_ids.catalog import (
    LEGACY_ATARI_GAMES,
    REMOVED_FAMILIES,
    RETIRED_IDS,
    EnvPackage,
    IdMigration,
    atari_migration,
    env_package,
    is_atari_id,
    migration_for,
    removed_family,
)

__all__ = [
    "LEGACY_ATARI_GAMES",
    "REMOVED_FAMILIES",
    "RETIRED_IDS",
    "EnvPackage",
    "IdMigration",
    "atari_migration",
    "env_package",
    "is_atari_id",
    "migration_for",
    "removed_family",
]
