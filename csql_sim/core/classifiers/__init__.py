"""The classifiers: R- and Q-classifiers, the one classifier list, lifted rules."""
