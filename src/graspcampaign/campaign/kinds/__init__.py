"""Trial kinds, one module per family; registered by name in ``campaign.kind.KINDS``."""
