"""Built-in data: the thesis' synthetic set (:mod:`.thesis`) and simulated human throws (:mod:`.throws`)."""
