# Placeholder: filled by the stress tests of issue 11.
