"""The paper's reproduction reports (Singh 2007): case 1, case 2 and the system scenes."""
