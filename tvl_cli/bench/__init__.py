"""`tvl bench`'s room: the shipped suites (generalization, claims), each a list of cells
(cells) planned from its options (options, generalization, claims, references, controllers),
done by the verbs' own work (work) on the sweep's engine with a journal to go on from
(runner)."""
