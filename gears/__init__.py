"""Gear theory in pure numpy, no FE: involute geometry, the closed-form models of the
references (singh2007, pust2016, parker2000), ISO 6336, Hertz. The bottom layer."""
